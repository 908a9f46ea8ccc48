#include "tests/support/PacsPeer.h"
#include "tests/support/TestCertificates.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "tests/support/ProcessRunner.h"

namespace hvx::test {

std::uint16_t freePort() {
    const int s = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
    ::close(s);
    return ntohs(a.sin_port);
}

bool waitForPort(std::uint16_t port, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        const int s = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = htons(port);
        const bool ok = ::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
        ::close(s);
        if (ok) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
}

PacsPeer::PacsPeer(Kind kind, bool tls, const std::string& certificateNames)
    : kind_(kind), tls_(tls), ae_(kind == Kind::Dcmqrscp ? "DCMQR" : "ORTHANC"), dicomPort_(freePort()), httpPort_(freePort()),
      localPort_(freePort()) {
    std::filesystem::create_directories(dir_.file("storage"));
    std::filesystem::create_directories(dir_.file("index"));
    std::string tlsConfig;
    if (tls_) {
        const std::string d = dir_.path().string();
        makeTestCertificates(d, certificateNames);
        tlsConfig = ", \"DicomTlsEnabled\": true, \"DicomTlsCertificate\": \"" + d + "/server.crt\", "
                    "\"DicomTlsPrivateKey\": \"" + d + "/server.key\", \"DicomTlsTrustedCertificates\": \"" + d +
                    "/ca.crt\", \"DicomTlsRemoteCertificateRequired\": false";
    }
    if (kind_ != Kind::Dcmqrscp) {
        const std::string plugins = kind_ == Kind::OrthancDicomWeb
                                        ? "[\"/usr/share/orthanc/plugins/libOrthancDicomWeb.so\"], \"DicomWeb\": "
                                          "{ \"Enable\": true, \"Root\": \"/dicom-web/\", \"EnableWado\": false }"
                                        : "[]";
        std::ofstream(dir_.file("orthanc.json"))
            << "{ \"Name\": \"HolovoxTest\", \"StorageDirectory\": \"" << dir_.file("storage")
            << "\", \"IndexDirectory\": \"" << dir_.file("index") << "\", \"HttpPort\": " << httpPort_
            << ", \"DicomPort\": " << dicomPort_ << ", \"DicomAet\": \"" << ae_
            << "\", \"RemoteAccessAllowed\": false, \"AuthenticationEnabled\": false,"
               " \"DicomCheckCalledAet\": true, \"DicomAlwaysAllowEcho\": true, \"DicomAlwaysAllowStore\": true,"
               " \"DicomCheckModalityHost\": false, \"StorageCompression\": false, \"Plugins\": "
            << plugins << ", \"DicomScpTimeout\": 30, \"DicomModalities\": { \"holovox\": [\"HOLOVOX\", \"127.0.0.1\", "
            << localPort_ << "], \"seeder\": [\"SEEDER\", \"127.0.0.1\", 1] }" << tlsConfig << " }\n";
    } else {
        std::ofstream(dir_.file("dcmqrscp.cfg"))
            << "NetworkTCPPort = " << dicomPort_ << "\nMaxPDUSize = 16384\nMaxAssociations = 16\n"
            << "HostTable BEGIN\nholovox = (HOLOVOX, 127.0.0.1, " << localPort_
            << ")\nseeder = (SEEDER, 127.0.0.1, 1)\nHostTable END\nVendorTable BEGIN\nVendorTable END\n"
            << "AETable BEGIN\n" << ae_ << " " << dir_.file("storage") << " RW (200, 1024mb) ANY\nAETable END\n";
    }
}

PacsPeer::~PacsPeer() {
    if (pid_ > 0) {
        ::kill(pid_, SIGTERM);
        for (int i = 0; i < 50; ++i) {
            if (::waitpid(pid_, nullptr, WNOHANG) == pid_) return;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, nullptr, 0);
    }
}

void PacsPeer::start() {
    pid_ = ::fork();
    if (pid_ == 0) {
        const int log = ::open(dir_.file("peer.log").c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        ::dup2(log, 1);
        ::dup2(log, 2);
        if (kind_ != Kind::Dcmqrscp)
            ::execlp("Orthanc", "Orthanc", dir_.file("orthanc.json").c_str(), static_cast<char*>(nullptr));
        else
            ::execlp("dcmqrscp", "dcmqrscp", "-c", dir_.file("dcmqrscp.cfg").c_str(), "--disable-host-lookup",
                     static_cast<char*>(nullptr));
        ::_exit(127);
    }
    if (!waitForPort(dicomPort_, 30)) throw std::runtime_error("PACS peer did not start; see " + dir_.file("peer.log"));
    if (kind_ == Kind::OrthancDicomWeb && !waitForPort(httpPort_, 30))
        throw std::runtime_error("Orthanc's HTTP server did not start; see " + dir_.file("peer.log"));
}

void PacsPeer::kill() {
    if (pid_ > 0) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, nullptr, 0);
        pid_ = -1;
    }
}

void PacsPeer::seed(const std::vector<std::string>& files) {
    // storescu takes many files at once; write the list to avoid huge command lines.
    std::string cmd = "storescu -aet SEEDER -aec " + ae_ + " 127.0.0.1 " + std::to_string(dicomPort_);
    for (const auto& f : files) cmd += " '" + f + "'";
    const auto r = runCommand(cmd + " 2>&1");
    if (r.exitCode != 0) throw std::runtime_error("storescu failed: " + r.output);
}

dicom::PacsSettings PacsPeer::settings() const {
    dicom::PacsSettings s;
    s.local.aeTitle = "HOLOVOX";
    s.local.port = localPort_;
    s.local.storageDir = receiveDir();
    s.local.timeoutSeconds = 10;
    dicom::PacsNode n;
    n.name = "peer";
    n.aeTitle = ae_;
    n.host = "127.0.0.1";
    n.port = dicomPort_;
    s.nodes.push_back(n);
    s.defaultNode = "peer";
    return s;
}

dicom::PacsSettings PacsPeer::webSettings() const {
    dicom::PacsSettings s = settings();
    dicom::PacsNode n;
    n.name = "web";
    n.kind = dicom::NodeKind::DicomWeb;
    n.baseUrl = dicomWebUrl();
    s.nodes.push_back(n);
    return s;
}

}  // namespace hvx::test
