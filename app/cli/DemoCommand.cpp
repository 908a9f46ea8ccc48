#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "app/cli/OctreeBuildRunner.h"
#include "core/base/Error.h"
#include "app/cli/DemoArchive.h"
#include "core/volume/VoxelSourceFactory.h"
#include "dicom/PacsClient.h"
#include "dicom/PacsSettings.h"

namespace hvx::app {

namespace {
std::filesystem::path dataDir() { return DemoArchive::dataFolder(); }
}  // namespace

int demoCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"input", "o", "output", "config"}, {"no-pacs", "stop", "status"});
    if (args.flag("stop") || args.flag("status")) {
        DemoArchive::Config archive;
        archive.folder = (dataDir() / "demo-archive").string();
        if (args.flag("stop")) {
            std::printf("%s\n", DemoArchive::stop(archive).c_str());
            return 0;
        }
        const std::string status = DemoArchive::status(archive);
        std::printf("demo archive: %s\n", status.c_str());
        return status == "stopped" ? 3 : 0;  // as LSB's "status": 3 when not running
    }
    const std::string mriTemplate = "/usr/share/mricron/templates/ch2better.nii.gz";
    std::string input = mriTemplate;
    if (const char* env = std::getenv("HOLOVOX_DEMO_DATA"); env && *env) input = env;
    if (const auto i = args.value("input")) input = *i;
    std::filesystem::path out = dataDir() / "demo" / "ch2better.hvo";
    if (const auto o = args.value("o") ? args.value("o") : args.value("output")) out = *o;
    std::error_code ec;
    std::filesystem::create_directories(out.parent_path(), ec);
    if (ec) throw core::Error(out.parent_path().string() + ": cannot create directory (" + ec.message() + ")");
    std::printf("Holovox demo: building the out-of-core octree of the MRI template\n  %s\n", input.c_str());
    auto source = core::VoxelSourceFactory::open(input);
    core::BuildOptions options;
    if (input == mriTemplate) options.modality = "MR";  // a T1 template, which its NIfTI cannot say
    OctreeBuildRunner::run(*source, out.string(), options, true);
    if (args.flag("no-pacs")) return 0;

    std::printf("\nHolovox demo: starting the demo archive (a local Orthanc on loopback)\n");
    DemoArchive::Config archive;
    archive.folder = (dataDir() / "demo-archive").string();
    archive.mriTemplate = input;
    const std::string settings = args.value("config").value_or(dicom::PacsSettings::defaultPath());
    std::printf("  %s\n", DemoArchive::ensure(archive, settings).c_str());
    const auto s = dicom::PacsSettings::load(settings);
    dicom::PacsClient(s.local, s.node("demo")).find(dicom::QueryLevel::Study, {}, [](const dicom::QueryResult& r) {
        std::printf("  study %-18s %-12s %s %-4s %-34s %d images\n", r.patientName.c_str(), r.patientId.c_str(),
                    r.studyDate.c_str(), r.modalitiesInStudy.c_str(), r.studyDescription.c_str(), r.numberOfInstances);
        return true;
    });
    std::printf("  try: holovox-cli pacs find demo --patient 'HOLOVOX*'   then   holovox-cli pacs get demo STUDY_UID\n");
    return 0;
}

}  // namespace hvx::app
