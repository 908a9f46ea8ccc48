#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dicom/PacsSettings.h"

namespace hvx::core {
class JobContext;
}

namespace hvx::app {

/// The embedded demo archive: a local Orthanc (Debian package) on loopback with a throwaway
/// configuration under the user's data folder, seeded with demo studies (the CT phantom and
/// the MRI template written as DICOM series with plausible patient and study attributes) and
/// registered as the default PACS node, so query/retrieve can be tried at once; with Debian's
/// orthanc-dicomweb plugin the same archive is also the DICOMweb node "demo-web". Orthanc keeps
/// running after the command (its pid in the folder's orthanc.pid); a second run reuses it;
/// stop() ends it. The demo series are written once into the folder and kept, so that the
/// archive and the workstation's study database hold the same instances (the same UIDs).
class DemoArchive {
public:
    struct Config {
        std::string folder;  ///< configuration, storage and logs
        std::uint16_t dicomPort = 4243;
        std::uint16_t httpPort = 8043;
        std::uint16_t localPort = 11112;  ///< Holovox's storage SCP, registered on Orthanc for C-MOVE
        std::string mriTemplate = "/usr/share/mricron/templates/ch2better.nii.gz";
    };
    /// The demo series as DICOM files: the CT phantom and (when the template is there) the MRI
    /// template, with plausible patient and study attributes.
    struct Series {
        std::string ctFolder, mrFolder;  ///< mrFolder empty without the template
        std::vector<std::string> files;
    };
    /// Writes the demo series into the folder once (whole or not at all: a series is written
    /// beside and renamed into place) and returns them; later calls return the same files.
    static Series series(const Config& config, core::JobContext& job);
    /// Starts (or finds) the archive, seeds it from series() when empty, saves the "demo" node as
    /// default into the settings file. Returns a one-line description; `started` says whether
    /// this call started Orthanc (false when it found it running). An Orthanc that exits at start
    /// (its port still held by one stopping, or taken) is started again up to three times, a
    /// little later each time. Throws core::Error when Orthanc is missing or cannot start (the
    /// message names the port and the log file).
    /// `stage` hears what it is doing and how far ("starting Orthanc", "seeding 12 of 480
    /// images"), from this thread.
    static std::string ensure(const Config& config, const std::string& settingsPath, bool* started = nullptr,
                              const std::function<void(double, const std::string&)>& stage = {});
    /// "running (Orthanc, pid N, DICOM on …)" when this archive's Orthanc runs, else "stopped".
    static std::string status(const Config& config);
    /// Stops this archive's Orthanc (SIGTERM, then SIGKILL after 10 s) and says so; an archive
    /// that is not running, or a process Holovox did not start, is left alone.
    static std::string stop(const Config& config);
    /// Holovox's data folder: $XDG_DATA_HOME/holovox, else ~/.local/share/holovox.
    static std::string dataFolder();
};

}  // namespace hvx::app
