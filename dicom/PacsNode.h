#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace hvx::dicom {

/// How a remote node prefers to send us images.
enum class RetrieveMethod { Get, Move };

/// The protocol a remote node speaks: DICOM's own network services (C-FIND/C-GET/C-MOVE/
/// C-STORE) or DICOMweb over HTTP (QIDO-RS/WADO-RS/STOW-RS).
enum class NodeKind { Dimse, DicomWeb };

/// The largest PDU Holovox offers to receive unless the settings say otherwise (DCMTK's
/// tools default to 16 KB; fewer, larger PDUs cost less per instance).
constexpr std::uint32_t kDefaultMaxPdu = 116794;

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
    std::uint32_t maxPdu = kDefaultMaxPdu;  ///< the largest PDU we offer to receive (4096 to 131072)

    NodeKind kind = NodeKind::Dimse;
    /// DICOMweb: the service's base URL ("http://host:8042/dicom-web"); host and port above are
    /// taken from it. aeTitle stays empty.
    std::string baseUrl;
    std::string bearerToken;            ///< DICOMweb: "Authorization: Bearer ..." when not empty
    std::string username, password;     ///< DICOMweb: HTTP basic authentication when username is set
    bool tlsVerify = true;              ///< DICOMweb over https: check the server's certificate and name
};

/// Holovox's own node: the AE title it calls with, the port its storage SCP listens on, where
/// received instances are stored, and which calling AE titles may push to it.
struct LocalNode {
    std::string aeTitle = "HOLOVOX";
    std::uint16_t port = 11112;
    /// The IPv4 address the storage SCP listens on; empty: all interfaces, as a DICOM node must be
    /// reachable by the modalities and archives that send to it.
    std::string bindAddress;
    std::string storageDir;
    std::vector<std::string> allowedCallers;  ///< empty: the AE titles of the configured nodes
    int timeoutSeconds = 30;                  ///< network timeout (connect, ACSE, DIMSE)
    std::uint32_t maxPdu = kDefaultMaxPdu;    ///< the largest PDU the storage SCP offers to receive
    /// How many series of a study are retrieved at once, each over its own association (and
    /// how many associations a C-STORE of many files uses).
    int parallelAssociations = 3;
    /// Below this free space on the storage folder's disk, instances are refused ("Out of
    /// Resources", A700) rather than written until the disk is full.
    std::uint64_t minFreeBytes = std::uint64_t(512) << 20;
    /// A pushed instance larger than this is cut off and its association aborted (no DICOM
    /// image a workstation reads comes near it; a hostile stream would fill the disk).
    std::uint64_t maxInstanceBytes = std::uint64_t(4) << 30;
    /// DICOM over TLS for the storage SCP (BCP 195), when a certificate and key are given: then
    /// it speaks TLS only. With tlsTrustedCertificate, callers must present a certificate that
    /// CA signed.
    std::string tlsCertificate;         ///< our PEM certificate
    std::string tlsPrivateKey;          ///< its PEM private key (unencrypted)
    std::string tlsTrustedCertificate;  ///< PEM CA(s) whose client certificates are required
};

}  // namespace hvx::dicom
