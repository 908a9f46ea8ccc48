#pragma once
#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

#include "dicom/PacsSettings.h"
#include "tests/support/TempDir.h"

namespace hvx::test {

/// A free TCP port on loopback (bound once and released; good enough for tests).
std::uint16_t freePort();
/// Waits until something accepts TCP connections on the port; false after `seconds`.
bool waitForPort(std::uint16_t port, double seconds);

/// A real PACS for tests, started on free loopback ports with a throwaway configuration and
/// storage: Orthanc (Debian package) or DCMTK's dcmqrscp. Holovox's storage SCP is registered
/// on the peer as a C-MOVE destination. Stopped and deleted on destruction.
class PacsPeer {
public:
    /// OrthancDicomWeb: Orthanc with its DICOMweb plugin (Debian's orthanc-dicomweb) serving
    /// QIDO-RS, WADO-RS and STOW-RS at dicomWebUrl().
    enum class Kind { Orthanc, OrthancDicomWeb, Dcmqrscp };
    /// With `tls`, Orthanc speaks DICOM over TLS only, with a CA and certificate made here by
    /// openssl (tlsCa() signs the server certificate).
    /// With `tls`, the peer's certificate names `certificateNames` (subjectAltName entries).
    explicit PacsPeer(Kind kind, bool tls = false, const std::string& certificateNames = "IP:127.0.0.1,DNS:localhost");
    ~PacsPeer();
    PacsPeer(const PacsPeer&) = delete;
    PacsPeer& operator=(const PacsPeer&) = delete;

    void start();
    /// SIGKILL, as a crash or a pulled cable would.
    void kill();
    /// Stores files on the peer with DCMTK's storescu; throws on failure.
    void seed(const std::vector<std::string>& files);
    /// Settings whose node "peer" is this server and whose local node receives into a folder.
    dicom::PacsSettings settings() const;
    std::uint16_t dicomPort() const { return dicomPort_; }
    std::uint16_t localPort() const { return localPort_; }
    const std::string& aeTitle() const { return ae_; }
    std::string receiveDir() const { return dir_.file("received"); }
    std::string file(const std::string& name) const { return dir_.file(name); }
    std::string tlsCa() const { return dir_.file("ca.crt"); }
    std::uint16_t httpPort() const { return httpPort_; }
    std::string dicomWebUrl() const { return "http://127.0.0.1:" + std::to_string(httpPort_) + "/dicom-web"; }
    /// Settings as settings(), with the node "web": this peer's DICOMweb service.
    dicom::PacsSettings webSettings() const;

private:
    Kind kind_;
    bool tls_;
    TempDir dir_;
    std::string ae_;
    std::uint16_t dicomPort_, httpPort_, localPort_;
    pid_t pid_ = -1;
};

}  // namespace hvx::test
