#include "dicom/PacsSettings.h"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/base/AtomicFileWriter.h"
#include "core/base/Error.h"
#include "dicom/DicomWebUrl.h"

namespace hvx::dicom {

namespace {
void checkAe(const std::string& ae, const std::string& what) {
    if (ae.empty() || ae.size() > 16 || ae.find('\\') != std::string::npos)
        throw core::Error(what + ": AE title '" + ae + "' must be 1 to 16 characters without backslash");
}

std::uint32_t checkPdu(std::int64_t pdu, const std::string& what) {
    if (pdu < 4096 || pdu > 131072)
        throw core::Error(what + ": maxPdu " + std::to_string(pdu) + " must be 4096 to 131072 bytes");
    return std::uint32_t(pdu);
}

PacsNode readNode(const nlohmann::json& n, const std::string& path) {
    PacsNode node;
    node.name = n.at("name").get<std::string>();
    const std::string where = path + ": node '" + node.name + "'";
    node.kind = n.value("kind", std::string("dimse")) == "dicomweb" ? NodeKind::DicomWeb : NodeKind::Dimse;
    if (node.kind == NodeKind::DicomWeb) {
        node.baseUrl = n.at("url").get<std::string>();
        DicomWebUrl::check(node.baseUrl, where);
        node.bearerToken = n.value("bearerToken", std::string());
        node.username = n.value("username", std::string());
        node.password = n.value("password", std::string());
        node.tlsVerify = n.value("tlsVerify", true);
        return node;
    }
    node.aeTitle = n.at("aeTitle").get<std::string>();
    node.host = n.at("host").get<std::string>();
    const int p = n.at("port").get<int>();
    if (p <= 0 || p > 65535) throw core::Error(where + " has an invalid port");
    node.port = std::uint16_t(p);
    node.retrieve = n.value("retrieve", std::string("get")) == "move" ? RetrieveMethod::Move : RetrieveMethod::Get;
    node.tls = n.value("tls", false);
    node.tlsTrustedCertificate = n.value("tlsTrustedCertificate", std::string());
    node.tlsCertificate = n.value("tlsCertificate", std::string());
    node.tlsPrivateKey = n.value("tlsPrivateKey", std::string());
    node.maxPdu = checkPdu(n.value("maxPdu", std::int64_t(node.maxPdu)), where);
    checkAe(node.aeTitle, where);
    return node;
}

nlohmann::json writeNode(const PacsNode& n) {
    if (n.kind == NodeKind::DicomWeb)
        return {{"name", n.name},         {"kind", "dicomweb"},        {"url", n.baseUrl},
                {"bearerToken", n.bearerToken}, {"username", n.username}, {"password", n.password},
                {"tlsVerify", n.tlsVerify}};
    return {{"name", n.name},
            {"aeTitle", n.aeTitle},
            {"host", n.host},
            {"port", n.port},
            {"retrieve", n.retrieve == RetrieveMethod::Move ? "move" : "get"},
            {"tls", n.tls},
            {"tlsTrustedCertificate", n.tlsTrustedCertificate},
            {"tlsCertificate", n.tlsCertificate},
            {"tlsPrivateKey", n.tlsPrivateKey},
            {"maxPdu", n.maxPdu}};
}

std::string dataHome() {
    if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x) return x;
    if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.local/share";
    return "/tmp";
}
}  // namespace

std::string PacsSettings::defaultPath() {
    if (const char* p = std::getenv("HOLOVOX_PACS_CONFIG"); p && *p) return p;
    if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x) return std::string(x) + "/holovox/pacs.json";
    if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.config/holovox/pacs.json";
    return "/tmp/holovox-pacs.json";
}

PacsSettings PacsSettings::load(const std::string& path) {
    PacsSettings s;
    s.local.storageDir = dataHome() + "/holovox/received";
    std::ifstream in(path);
    if (!in) return s;
    nlohmann::json j;
    try {
        in >> j;
        const auto& l = j.at("local");
        s.local.aeTitle = l.value("aeTitle", s.local.aeTitle);
        const int port = l.value("port", int(s.local.port));
        if (port <= 0 || port > 65535) throw core::Error(path + ": local port " + std::to_string(port) + " is invalid");
        s.local.port = std::uint16_t(port);
        s.local.bindAddress = l.value("bindAddress", std::string());
        s.local.storageDir = l.value("storageDir", s.local.storageDir);
        s.local.allowedCallers = l.value("allowedCallers", std::vector<std::string>{});
        s.local.timeoutSeconds = l.value("timeoutSeconds", s.local.timeoutSeconds);
        s.local.minFreeBytes = std::uint64_t(l.value("minFreeMiB", s.local.minFreeBytes >> 20)) << 20;
        s.local.maxInstanceBytes = std::uint64_t(l.value("maxInstanceMiB", s.local.maxInstanceBytes >> 20)) << 20;
        if (s.local.maxInstanceBytes == 0) throw core::Error(path + ": local maxInstanceMiB must be at least 1");
        s.local.tlsCertificate = l.value("tlsCertificate", std::string());
        s.local.tlsPrivateKey = l.value("tlsPrivateKey", std::string());
        s.local.tlsTrustedCertificate = l.value("tlsTrustedCertificate", std::string());
        checkAe(s.local.aeTitle, path);
        s.local.maxPdu = checkPdu(l.value("maxPdu", s.local.maxPdu), path + ": local");
        s.local.parallelAssociations = l.value("parallelAssociations", s.local.parallelAssociations);
        if (s.local.parallelAssociations < 1 || s.local.parallelAssociations > 16)
            throw core::Error(path + ": local parallelAssociations must be 1 to 16");
        for (const auto& n : j.value("nodes", nlohmann::json::array())) s.nodes.push_back(readNode(n, path));
        s.defaultNode = j.value("default", std::string());
    } catch (const nlohmann::json::exception& e) {
        throw core::Error(path + ": malformed PACS settings (" + e.what() + ")");
    }
    return s;
}

void PacsSettings::save(const std::string& path) const {
    nlohmann::json j;
    j["local"] = {{"aeTitle", local.aeTitle},       {"port", local.port}, {"bindAddress", local.bindAddress},
                  {"storageDir", local.storageDir},
                  {"allowedCallers", local.allowedCallers}, {"timeoutSeconds", local.timeoutSeconds},
                  {"minFreeMiB", local.minFreeBytes >> 20}, {"maxInstanceMiB", local.maxInstanceBytes >> 20},
                  {"tlsCertificate", local.tlsCertificate}, {"tlsPrivateKey", local.tlsPrivateKey},
                  {"tlsTrustedCertificate", local.tlsTrustedCertificate}, {"maxPdu", local.maxPdu},
                  {"parallelAssociations", local.parallelAssociations}};
    j["nodes"] = nlohmann::json::array();
    for (const auto& n : nodes) j["nodes"].push_back(writeNode(n));
    j["default"] = defaultNode;
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    const std::string text = j.dump(2) + "\n";
    core::AtomicFileWriter out(path);
    out.append(text.data(), text.size());
    out.commit();
    // Credentials of DICOMweb nodes: the file is for its owner's eyes only.
    bool secrets = false;
    for (const auto& n : nodes) secrets = secrets || !n.password.empty() || !n.bearerToken.empty();
    if (secrets)
        std::filesystem::permissions(path, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write,
                                     std::filesystem::perm_options::replace, ec);
}

const PacsNode& PacsSettings::node(const std::string& name) const {
    const std::string want = name.empty() ? defaultNode : name;
    for (const auto& n : nodes)
        if (n.name == want) return n;
    std::string known;
    for (const auto& n : nodes) known += (known.empty() ? "" : ", ") + n.name;
    throw core::Error("no PACS node named '" + want + "' (configured: " + (known.empty() ? "none" : known) + ")");
}

void PacsSettings::upsert(const PacsNode& node) {
    for (auto& n : nodes)
        if (n.name == node.name) {
            n = node;
            return;
        }
    nodes.push_back(node);
}

}  // namespace hvx::dicom
