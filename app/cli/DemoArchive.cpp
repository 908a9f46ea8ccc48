#include "app/cli/DemoArchive.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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

/// Starts Orthanc on the archive's configuration; returns its pid.
pid_t startOrthanc(const DemoArchive::Config& c) {
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
    return pid;
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

/// Writes one demo series into `folder` unless it is there (the writer renames a series into
/// place only when whole, so a write cut short leaves nothing that looks complete).
std::vector<std::string> writeOnce(const fs::path& folder, core::VoxelSource& source, const dicom::DicomWriteOptions& o,
                                   core::JobContext& job) {
    std::vector<std::string> files;
    if (!fs::exists(folder)) dicom::DicomSeriesWriter::write(source, folder.string(), o, job);
    for (const auto& e : fs::directory_iterator(folder))
        if (e.is_regular_file()) files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    return files;
}

void seed(const DemoArchive::Config& c, const dicom::LocalNode& local, const dicom::PacsNode& node,
          const std::function<void(double, const std::string&)>& stage) {
    core::JobContext job;
    const auto files = DemoArchive::series(c, job).files;
    const std::string total = std::to_string(files.size());
    if (stage) stage(0.0, "seeding 0 of " + total + " images");
    dicom::PacsClient(local, node).store(files, [&](std::size_t done) {
        if (stage) stage(double(done) / double(std::max<std::size_t>(1, files.size())),
                         "seeding " + std::to_string(done) + " of " + total + " images");
    });
}
}  // namespace

DemoArchive::Series DemoArchive::series(const Config& c, core::JobContext& job) {
    const fs::path dir = fs::path(c.folder) / "series";
    fs::create_directories(dir);
    fs::remove_all(fs::path(c.folder) / "seed");  // where earlier versions wrote them for a moment
    Series out;
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
    out.ctFolder = (dir / "ct").string();
    out.files = writeOnce(out.ctFolder, phantom, ct, job);
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
        out.mrFolder = (dir / "mr").string();
        const auto files = writeOnce(out.mrFolder, *mri, mr, job);
        out.files.insert(out.files.end(), files.begin(), files.end());
    }
    return out;
}

std::string DemoArchive::ensure(const Config& c, const std::string& settingsPath, bool* started,
                                const std::function<void(double, const std::string&)>& stage) {
    if (started) *started = false;
    auto settings = dicom::PacsSettings::load(settingsPath);
    settings.local.port = c.localPort;
    dicom::PacsNode node;
    node.name = "demo";
    node.aeTitle = "ORTHANC";
    node.host = "127.0.0.1";
    node.port = c.dicomPort;
    settings.local.timeoutSeconds = 5;
    if (!answers(settings.local, node)) {
        // One of ours that does not answer (stopping, or hung) goes first: it may hold the port.
        if (archivePid(c) != 0) stop(c);
        if (stage) stage(0.0, "starting Orthanc");
        bool up = false, exited = false;
        for (int attempt = 0; attempt < 3 && !up; ++attempt) {
            if (attempt > 0) std::this_thread::sleep_for(std::chrono::seconds(attempt));  // the port may be freed by then
            const pid_t pid = startOrthanc(c);
            exited = false;
            for (int i = 0; i < 150 && !up && !exited; ++i) {
                std::this_thread::sleep_for(std::chrono::milliseconds(200));
                int status = 0;
                exited = ::waitpid(pid, &status, WNOHANG) == pid;  // it gave up (a port taken, a bad folder)
                up = !exited && answers(settings.local, node);
            }
            if (!up && !exited) {  // neither up nor gone after 30 s: not ours to keep
                ::kill(pid, SIGKILL);
                ::waitpid(pid, nullptr, 0);
            }
        }
        if (!up)
            throw core::Error("the demo archive (Orthanc on port " + std::to_string(c.dicomPort) + ") did not start" +
                              (exited ? std::string(": it exited at once, three times (is port ") +
                                            std::to_string(c.dicomPort) + " or " + std::to_string(c.httpPort) +
                                            " taken by another program?)"
                                      : std::string(" within 30 s")) +
                              "; see " + c.folder + "/orthanc.log");
        if (started) *started = true;
    }
    std::size_t studies = dicom::PacsClient(settings.local, node).find(dicom::QueryLevel::Study, {}, {});
    if (studies == 0) {
        seed(c, settings.local, node, stage);
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
