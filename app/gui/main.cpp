// holovox: the workstation GUI. `holovox [FILE.hvo|DICOM-FOLDER|DICOMDIR|DICOM-FILE]` opens
// directly; `holovox --demo` starts the demo archive, connects it and opens the demo study.
#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QFileInfo>
#include <QPointer>
#include <QTimer>

#include <filesystem>

#include "app/cli/DemoArchive.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/VoxelSourceFactory.h"
#include "dicom/PacsSettings.h"
#include "ui/JobManager.h"
#include "ui/MainWindow.h"
#include "ui/PacsPanel.h"
#include "ui/VolumeView.h"

namespace {
// The demo: the MRI template's octree (built once) and the demo archive, both in the background.
void startDemo(hvx::ui::MainWindow& window, const QString& pacsConfig) {
    const std::filesystem::path data = hvx::app::DemoArchive::dataFolder();
    std::string input = "/usr/share/mricron/templates/ch2better.nii.gz";
    if (const char* env = std::getenv("HOLOVOX_DEMO_DATA"); env && *env) input = env;
    const std::string octree = (data / "demo" / "ch2better.hvo").string();
    QPointer<hvx::ui::MainWindow> w(&window);
    window.jobs()->start(
        QObject::tr("Demo study"),
        [input, octree](hvx::core::JobContext& job) {
            if (!std::filesystem::exists(octree)) {
                std::filesystem::create_directories(std::filesystem::path(octree).parent_path());
                auto source = hvx::core::VoxelSourceFactory::open(input);
                hvx::core::OctreeBuilder(hvx::core::BuildOptions{}).build(*source, octree, job);
            }
            return QString::fromStdString(octree);
        },
        [w](const QString& path) {
            if (w) w->openOctree(path, QObject::tr("Demo: MRI template (ch2better)"));
        });
    const std::string settings = pacsConfig.isEmpty() ? hvx::dicom::PacsSettings::defaultPath() : pacsConfig.toStdString();
    window.jobs()->start(
        QObject::tr("Demo archive (Orthanc)"),
        [input, data, settings](hvx::core::JobContext&) {
            hvx::app::DemoArchive::Config archive;
            archive.folder = (data / "demo-archive").string();
            archive.mriTemplate = input;
            return QString::fromStdString(hvx::app::DemoArchive::ensure(archive, settings));
        },
        [w](const QString&) {
            if (w) w->pacs()->reloadSettings();
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
    if (parser.isSet(demo)) startDemo(window, parser.value(pacs));
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
    return QApplication::exec();
}
