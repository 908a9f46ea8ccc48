#include "app/cli/DemoArchive.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "core/base/Error.h"
#include "core/base/JobContext.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "dicom/DicomSeriesWriter.h"
#include "dicom/PacsClient.h"

namespace fs = std::filesystem;

namespace hvx::app {

namespace {
bool answers(const dicom::LocalNode& local, const dicom::PacsNode& node) {
    try {
        dicom::PacsClient(local, node).echo();
        return true;
    } catch (const core::Error&) {
        return false;
    }
}

/// Debian's orthanc-dicomweb: the demo archive then serves DICOMweb too.
const char* kDicomWebPlugin = "/usr/share/orthanc/plugins/libOrthancDicomWeb.so";

void startOrthanc(const DemoArchive::Config& c) {
    fs::create_directories(fs::path(c.folder) / "storage");
    const std::string plugins = fs::exists(kDicomWebPlugin)
                                    ? std::string("[\"") + kDicomWebPlugin +
                                          "\"],\n  \"DicomWeb\": { \"Enable\": true, \"Root\": \"/dicom-web/\" }"
                                    : std::string("[]");
    const std::string config = (fs::path(c.folder) / "orthanc.json").string();
    std::ofstream(config) << "{\n  \"Name\": \"Holovox demo archive\",\n  \"StorageDirectory\": \"" << c.folder
                          << "/storage\",\n  \"IndexDirectory\": \"" << c.folder << "/storage\",\n  \"HttpPort\": "
                          << c.httpPort << ",\n  \"DicomPort\": " << c.dicomPort
                          << ",\n  \"DicomAet\": \"ORTHANC\",\n  \"RemoteAccessAllowed\": false,\n"
                             "  \"AuthenticationEnabled\": false,\n  \"DicomAlwaysAllowEcho\": true,\n"
                             "  \"DicomAlwaysAllowStore\": true,\n  \"DicomCheckModalityHost\": false,\n"
                             "  \"Plugins\": "
                          << plugins << ",\n  \"DicomModalities\": { \"holovox\": [\"HOLOVOX\", \"127.0.0.1\", "
                          << c.localPort << "] }\n}\n";
    const std::string log = (fs::path(c.folder) / "orthanc.log").string();
    const pid_t pid = ::fork();
    if (pid < 0) throw core::Error("cannot start Orthanc (fork failed)");
    if (pid == 0) {
        ::setsid();  // keeps running after holovox-cli exits
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        ::dup2(fd, 1);
        ::dup2(fd, 2);
        ::execlp("Orthanc", "Orthanc", config.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    std::ofstream(fs::path(c.folder) / "orthanc.pid") << pid << "\n";  // for demo --stop and --status
}

/// The pid of the demo archive's Orthanc when that process is alive (not a zombie) and is the
/// Orthanc started with this archive's configuration; 0 otherwise.
pid_t archivePid(const DemoArchive::Config& c) {
    pid_t pid = 0;
    std::ifstream(fs::path(c.folder) / "orthanc.pid") >> pid;
    if (pid <= 0) return 0;
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string name, state;
    pid_t ignored = 0;
    if (!(stat >> ignored >> name >> state) || state == "Z") return 0;
    std::ifstream cmd("/proc/" + std::to_string(pid) + "/cmdline");
    const std::string line((std::istreambuf_iterator<char>(cmd)), std::istreambuf_iterator<char>());
    const std::string config = (fs::path(c.folder) / "orthanc.json").string();
    return line.find("Orthanc") != std::string::npos && line.find(config) != std::string::npos ? pid : 0;
}

void seed(const DemoArchive::Config& c, const dicom::LocalNode& local, const dicom::PacsNode& node) {
    const fs::path dir = fs::path(c.folder) / "seed";
    core::JobContext job;
    std::vector<std::string> files;
    dicom::DicomWriteOptions ct;
    ct.patientName = "HOLOVOX^PHANTOM";
    ct.patientId = "HVX-CT-0001";
    ct.patientBirthDate = "19650412";
    ct.patientSex = "F";
    ct.studyDescription = "CT THORAX ABDOMEN WITH CONTRAST";
    ct.seriesDescription = "Axial 2.0 mm soft tissue";
    ct.accessionNumber = "HVX000101";
    ct.modality = "CT";
    core::PhantomVoxelSource phantom({256, 256, 160}, 2024);
    for (auto& f : dicom::DicomSeriesWriter::write(phantom, (dir / "ct").string(), ct, job)) files.push_back(f);
    if (fs::exists(c.mriTemplate)) {
        dicom::DicomWriteOptions mr;
        mr.patientName = "HOLOVOX^BRAIN";
        mr.patientId = "HVX-MR-0002";
        mr.patientBirthDate = "19800923";
        mr.patientSex = "M";
        mr.studyDescription = "MR HEAD T1 (ch2better template)";
        mr.seriesDescription = "T1 3D 0.5 mm";
        mr.accessionNumber = "HVX000102";
        mr.modality = "MR";
        auto mri = core::VoxelSourceFactory::open(c.mriTemplate);
        for (auto& f : dicom::DicomSeriesWriter::write(*mri, (dir / "mr").string(), mr, job)) files.push_back(f);
    }
    dicom::PacsClient(local, node).store(files, {});
    fs::remove_all(dir);
}
}  // namespace

std::string DemoArchive::ensure(const Config& c, const std::string& settingsPath) {
    auto settings = dicom::PacsSettings::load(settingsPath);
    settings.local.port = c.localPort;
    dicom::PacsNode node;
    node.name = "demo";
    node.aeTitle = "ORTHANC";
    node.host = "127.0.0.1";
    node.port = c.dicomPort;
    settings.local.timeoutSeconds = 5;
    if (!answers(settings.local, node)) {
        startOrthanc(c);
        bool up = false;
        for (int i = 0; i < 150 && !up; ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            up = answers(settings.local, node);
        }
        if (!up)
            throw core::Error("the demo archive (Orthanc on port " + std::to_string(c.dicomPort) +
                              ") did not start; see " + c.folder + "/orthanc.log");
    }
    std::size_t studies = dicom::PacsClient(settings.local, node).find(dicom::QueryLevel::Study, {}, {});
    if (studies == 0) {
        seed(c, settings.local, node);
        studies = dicom::PacsClient(settings.local, node).find(dicom::QueryLevel::Study, {}, {});
    }
    // The same archive over DICOMweb, when its plugin answers.
    dicom::PacsNode web;
    web.name = "demo-web";
    web.kind = dicom::NodeKind::DicomWeb;
    web.baseUrl = "http://127.0.0.1:" + std::to_string(c.httpPort) + "/dicom-web";
    const bool hasWeb = answers(settings.local, web);
    settings.local.timeoutSeconds = 30;
    settings.upsert(node);
    if (hasWeb) settings.upsert(web);
    settings.defaultNode = "demo";
    settings.save(settingsPath);
    return "Orthanc (AE ORTHANC) on 127.0.0.1:" + std::to_string(c.dicomPort) + " with " + std::to_string(studies) +
           " demo studies, saved as default node 'demo'" +
           (hasWeb ? " and DICOMweb node 'demo-web' (" + web.baseUrl + ")" : std::string()) + " in " + settingsPath;
}

std::string DemoArchive::status(const Config& c) {
    const pid_t pid = archivePid(c);
    if (pid == 0) return "stopped";
    return "running (Orthanc, pid " + std::to_string(pid) + ", DICOM on 127.0.0.1:" + std::to_string(c.dicomPort) +
           ", HTTP on 127.0.0.1:" + std::to_string(c.httpPort) + ", folder " + c.folder + ")";
}

std::string DemoArchive::stop(const Config& c) {
    const pid_t pid = archivePid(c);
    if (pid == 0) {
        fs::remove(fs::path(c.folder) / "orthanc.pid");
        return "the demo archive is not running";
    }
    ::kill(pid, SIGTERM);  // Orthanc closes its database cleanly on SIGTERM
    for (int i = 0; i < 100 && archivePid(c) != 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (archivePid(c) != 0) {
        ::kill(pid, SIGKILL);
        for (int i = 0; i < 20 && archivePid(c) != 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        if (archivePid(c) != 0) throw core::Error("the demo archive (Orthanc, pid " + std::to_string(pid) + ") did not stop");
    }
    fs::remove(fs::path(c.folder) / "orthanc.pid");
    return "stopped the demo archive (Orthanc, pid " + std::to_string(pid) + ")";
}

std::string DemoArchive::dataFolder() {
    if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x) return (std::filesystem::path(x) / "holovox").string();
    if (const char* h = std::getenv("HOME"); h && *h) return (std::filesystem::path(h) / ".local/share/holovox").string();
    return (std::filesystem::temp_directory_path() / "holovox").string();
}

}  // namespace hvx::app
