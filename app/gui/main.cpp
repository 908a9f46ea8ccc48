// holovox: the workstation GUI. `holovox [FILE.hvo|DICOM-FOLDER|DICOMDIR|DICOM-FILE]` opens
// directly; `holovox --demo` imports and opens the demo study and starts the demo archive (stopped
// on quit unless the PACS panel's "keep running" is ticked).
#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QElapsedTimer>
#include <QThread>
#include <QFileInfo>
#include <QPointer>
#include <QTimer>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/cli/DemoArchive.h"
#include "core/base/JobContext.h"
#include "dicom/PacsSettings.h"
#include "ui/JobManager.h"
#include "ui/MainWindow.h"
#include "ui/PacsPanel.h"
#include "ui/VolumeView.h"

namespace {
/// What the demo started, for the quit.
struct DemoState {
    hvx::app::DemoArchive::Config archive;
    std::atomic<bool> startedArchive{false};  // set by the archive's job
    bool archiveJobRunning = false;           // GUI thread
};

// The demo: its series written once as DICOM (the archive is seeded from the same files), the MRI
// template's imported into the study database like any import and opened; then the demo archive,
// found running or started, its state in the PACS panel.
void startDemo(hvx::ui::MainWindow& window, const QString& pacsConfig, const std::shared_ptr<DemoState>& state) {
    const std::filesystem::path data = hvx::app::DemoArchive::dataFolder();
    state->archive.folder = (data / "demo-archive").string();
    if (const char* env = std::getenv("HOLOVOX_DEMO_DATA"); env && *env) state->archive.mriTemplate = env;
    const std::string settings = pacsConfig.isEmpty() ? hvx::dicom::PacsSettings::defaultPath() : pacsConfig.toStdString();
    QPointer<hvx::ui::MainWindow> w(&window);
    window.pacs()->setDemoStatus(QObject::tr("starting\u2026"));
    const auto archiveJob = [w, state, settings] {
        if (!w) return;
        state->archiveJobRunning = true;
        const int id = w->jobs()->start(
            QObject::tr("Demo archive (Orthanc)"),
            [state, settings](hvx::core::JobContext& job) {
                bool started = false;
                const std::string text = hvx::app::DemoArchive::ensure(
                    state->archive, settings, &started,
                    [&job](double fraction, const std::string& stage) { job.report(fraction, stage); });
                state->startedArchive = started;
                return QString::fromStdString(text);
            },
            [w](const QString& text) {
                if (!w) return;
                w->pacs()->reloadSettings();
                w->pacs()->setDemoStatus(QObject::tr("ready: %1").arg(text));
            });
        // What it is doing (starting, seeding n of N) in the PACS panel as it goes.
        // The log says when each stage begins and when seeding ends, not every image.
        auto said = std::make_shared<QString>();
        QObject::connect(w->jobs(), &hvx::ui::JobManager::progressed, w,
                         [w, id, said](int job, double fraction, double, const QString& stage) {
                             if (!w || job != id || stage.isEmpty()) return;
                             w->pacs()->setDemoStatus(stage + QStringLiteral("\u2026"));
                             const QString first = stage.section(' ', 0, 0);
                             if (first != *said || fraction >= 1.0) {
                                 std::fprintf(stderr, "holovox: demo archive: %s\n", qPrintable(stage));
                                 *said = fraction >= 1.0 ? QString() : first;
                             }
                         });
        QObject::connect(w->jobs(), &hvx::ui::JobManager::finished, w, [w, id, state](int done, const QString& st, const QString& why) {
            if (done != id) return;
            state->archiveJobRunning = false;
            if (w && st != "done") w->pacs()->setDemoStatus(QStringLiteral("%1: %2").arg(st, why));
        });
    };
    window.jobs()->start(
        QObject::tr("Demo series"),
        [state](hvx::core::JobContext& job) {
            const auto series = hvx::app::DemoArchive::series(state->archive, job);
            return QString::fromStdString(series.mrFolder.empty() ? series.ctFolder : series.mrFolder);
        },
        [w, archiveJob](const QString& folder) {
            if (w) w->openPath(folder);  // imported (thumbnail, octree) and opened, selected in the browser
            archiveJob();
        });
}
}  // namespace

int main(int argc, char** argv) {
    hvx::ui::VolumeView::requestGlFormat();
    QApplication app(argc, argv);
    QApplication::setApplicationName("Holovox");
    QApplication::setOrganizationName("Holovox");
    QApplication::setApplicationVersion(HVX_VERSION);
    QCommandLineParser parser;
    parser.setApplicationDescription("Holovox medical volume workstation");
    parser.addHelpOption();
    parser.addVersionOption();
    parser.addPositionalArgument("file", "An .hvo octree, a DICOM folder or DICOMDIR, or a DICOM file to open");
    const QCommandLineOption demo("demo", "Start the demo archive, connect it and open the demo study.");
    const QCommandLineOption db("db", "The study database (default: $HOLOVOX_DB or the user's data folder).", "file");
    const QCommandLineOption pacs("pacs-config", "The PACS settings file (default: $HOLOVOX_PACS_CONFIG).", "file");
    const QCommandLineOption screenshot("screenshot", "Once a complete frame is shown, save a PNG of the window and quit.", "png");
    parser.addOption(demo);
    parser.addOption(db);
    parser.addOption(pacs);
    parser.addOption(screenshot);
    parser.process(app);

    hvx::ui::MainWindow window(parser.value(db), parser.value(pacs));
    window.show();
    auto demoState = std::make_shared<DemoState>();
    if (parser.isSet(demo)) startDemo(window, parser.value(pacs), demoState);
    else if (!parser.positionalArguments().isEmpty()) window.openPath(parser.positionalArguments().first());
    if (parser.isSet(screenshot)) {
        const QString out = parser.value(screenshot);
        auto grab = [&window, out] {
            window.grab().save(out);
            QApplication::quit();
        };
        // Once a complete, full-quality frame is shown (or after 60 s when nothing opens).
        auto* view = window.view();
        QObject::connect(view, &hvx::ui::VolumeView::frameRendered, &window, [view, grab] {
            static bool done = false;
            if (!done && view->readouts().complete && view->readouts().resolution >= 1.0) {
                done = true;
                QTimer::singleShot(500, grab);
            }
        });
        QTimer::singleShot(60000, &window, grab);
    }
    const int code = QApplication::exec();
    // The demo archive this session started is Holovox's: it stops with it, unless kept. One
    // still starting is let finish first (stopped half-way, its job would start it again).
    if (demoState->archiveJobRunning && !hvx::ui::PacsPanel::keepDemoRunning()) {
        std::fprintf(stderr, "holovox: waiting for the demo archive to finish starting, to stop it\n");
        QElapsedTimer waited;
        waited.start();
        while (demoState->archiveJobRunning && waited.elapsed() < 120000) {
            QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
            QThread::msleep(20);
        }
    }
    if (demoState->startedArchive && !hvx::ui::PacsPanel::keepDemoRunning()) {
        try {
            std::fprintf(stderr, "%s\n", hvx::app::DemoArchive::stop(demoState->archive).c_str());
        } catch (const std::exception& e) {
            std::fprintf(stderr, "holovox: %s\n", e.what());
        }
    }
    return code;
}
