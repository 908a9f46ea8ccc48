#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace hvx::dicom {

/// How a remote node prefers to send us images.
enum class RetrieveMethod { Get, Move };

/// A remote DICOM node (PACS, workstation, modality) as configured by the user.
struct PacsNode {
    std::string name;     ///< the user's name for it ("orthanc", "hospital-pacs")
    std::string aeTitle;  ///< its called AE title
    std::string host;
    std::uint16_t port = 104;
    RetrieveMethod retrieve = RetrieveMethod::Get;
    bool tls = false;  ///< DICOM over TLS (DCMTK dcmtls, BCP 195 profile)
    std::string tlsTrustedCertificate;  ///< PEM file of the CA(s) that sign the node's certificate
    std::string tlsCertificate;         ///< our PEM certificate, when the node requires one
    std::string tlsPrivateKey;          ///< our PEM private key (unencrypted), with tlsCertificate
};

/// Holovox's own node: the AE title it calls with, the port its storage SCP listens on, where
/// received instances are stored, and which calling AE titles may push to it.
struct LocalNode {
    std::string aeTitle = "HOLOVOX";
    std::uint16_t port = 11112;
    std::string storageDir;
    std::vector<std::string> allowedCallers;  ///< empty: the AE titles of the configured nodes
    int timeoutSeconds = 30;                  ///< network timeout (connect, ACSE, DIMSE)
};

}  // namespace hvx::dicom
