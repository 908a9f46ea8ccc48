#pragma once
#include <cstdint>
#include <string>

#include "dicom/PacsSettings.h"

namespace hvx::app {

/// The embedded demo archive: a local Orthanc (Debian package) on loopback with a throwaway
/// configuration under the user's data folder, seeded with demo studies (the CT phantom and
/// the MRI template written as DICOM series with plausible patient and study attributes) and
/// registered as the default PACS node, so query/retrieve can be tried at once; with Debian's
/// orthanc-dicomweb plugin the same archive is also the DICOMweb node "demo-web". Orthanc keeps
/// running after the command (its pid in the folder's orthanc.pid); a second run reuses it;
/// stop() ends it.
class DemoArchive {
public:
    struct Config {
        std::string folder;  ///< configuration, storage and logs
        std::uint16_t dicomPort = 4243;
        std::uint16_t httpPort = 8043;
        std::uint16_t localPort = 11112;  ///< Holovox's storage SCP, registered on Orthanc for C-MOVE
        std::string mriTemplate = "/usr/share/mricron/templates/ch2better.nii.gz";
    };
    /// Starts (or finds) the archive, seeds it when empty, saves the "demo" node as default into
    /// the settings file. Returns a one-line description. Throws core::Error when Orthanc is
    /// missing or cannot start (the message names the log file).
    static std::string ensure(const Config& config, const std::string& settingsPath);
    /// "running (Orthanc, pid N, DICOM on …)" when this archive's Orthanc runs, else "stopped".
    static std::string status(const Config& config);
    /// Stops this archive's Orthanc (SIGTERM, then SIGKILL after 10 s) and says so; an archive
    /// that is not running, or a process Holovox did not start, is left alone.
    static std::string stop(const Config& config);
    /// Holovox's data folder: $XDG_DATA_HOME/holovox, else ~/.local/share/holovox.
    static std::string dataFolder();
};

}  // namespace hvx::app
