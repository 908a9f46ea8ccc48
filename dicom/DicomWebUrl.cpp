#include "dicom/DicomWebUrl.h"

#include <cctype>

#include "core/base/Error.h"

namespace hvx::dicom {

DicomWebUrl DicomWebUrl::parse(const std::string& url, const std::string& where) {
    DicomWebUrl u;
    const auto sep = url.find("://");
    if (sep == std::string::npos) throw core::Error(where + ": '" + url + "' is not a URL (it needs http:// or https://)");
    u.scheme = url.substr(0, sep);
    for (auto& c : u.scheme) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (u.scheme != "http" && u.scheme != "https")
        throw core::Error(where + ": '" + url + "' is not an http or https URL");
    const std::string rest = url.substr(sep + 3);
    const auto slash = rest.find('/');
    const std::string authority = rest.substr(0, slash);
    u.path = slash == std::string::npos ? std::string() : rest.substr(slash);
    while (!u.path.empty() && u.path.back() == '/') u.path.pop_back();
    if (authority.find('@') != std::string::npos)
        throw core::Error(where + ": put the user name and password in the node's settings, not in the URL");
    if (u.path.find_first_of("?#") != std::string::npos)
        throw core::Error(where + ": the DICOMweb URL must be the service root, without a query ('" + url + "')");
    std::string port;
    if (!authority.empty() && authority[0] == '[') {  // [IPv6]:port
        const auto close = authority.find(']');
        if (close == std::string::npos) throw core::Error(where + ": '" + url + "' has an unclosed IPv6 address");
        u.host = authority.substr(1, close - 1);
        if (close + 1 < authority.size() && authority[close + 1] == ':') port = authority.substr(close + 2);
    } else {
        const auto colon = authority.rfind(':');
        u.host = authority.substr(0, colon);
        if (colon != std::string::npos) port = authority.substr(colon + 1);
    }
    if (u.host.empty()) throw core::Error(where + ": '" + url + "' names no host");
    u.port = u.scheme == "https" ? 443 : 80;
    if (!port.empty()) {
        long p = 0;
        for (char c : port) {
            if (!std::isdigit(static_cast<unsigned char>(c)) || p > 65535) {
                p = -1;
                break;
            }
            p = p * 10 + (c - '0');
        }
        if (p <= 0 || p > 65535) throw core::Error(where + ": '" + url + "' has an invalid port");
        u.port = std::uint16_t(p);
    }
    return u;
}

std::string DicomWebUrl::root(const std::string& url) {
    std::string r = url;
    while (!r.empty() && r.back() == '/') r.pop_back();
    return r;
}

std::string DicomWebUrl::encode(const std::string& value) {
    static const char* hex = "0123456789ABCDEF";
    std::string out;
    for (unsigned char c : value) {
        if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || c == '*' || c == '?' || c == '^' || c == ',') {
            out += char(c);
        } else {
            out += '%';
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    return out;
}

}  // namespace hvx::dicom
