#include <QApplication>
#include <QCommandLineParser>
#include <QFile>
#include <QPlainTextEdit>
#include <QScreen>
#include <QTimer>

#include "ui/MainWindow.h"

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setApplicationName("Holovox");
    QApplication::setOrganizationName("Holovox");
    QCommandLineParser parser;
    parser.setApplicationDescription("Holovox medical volume workstation");
    parser.addHelpOption();
    parser.addPositionalArgument("file", "An .hvo octree to open");
    const QCommandLineOption screenshot("screenshot", "Save a PNG of the window once shown, then quit.", "png");
    const QCommandLineOption dumpSummary("dump-summary", "Write the shown summary text to a file (tests).", "txt");
    parser.addOption(screenshot);
    parser.addOption(dumpSummary);
    parser.process(app);
    hvx::ui::MainWindow window;
    if (!parser.positionalArguments().isEmpty()) window.openOctree(parser.positionalArguments().first());
    window.show();
    if (parser.isSet(screenshot)) {
        QTimer::singleShot(500, &window, [&] {
            window.grab().save(parser.value(screenshot));
            if (parser.isSet(dumpSummary)) {
                QFile f(parser.value(dumpSummary));
                if (f.open(QIODevice::WriteOnly)) f.write(window.findChild<QPlainTextEdit*>()->toPlainText().toUtf8());
            }
            QApplication::quit();
        });
    }
    return QApplication::exec();
}
