#pragma once
#include <cstdint>
#include <string>

namespace hvx::dicom {

/// The parts of a DICOMweb base URL that Holovox shows and checks: scheme, host, port, path.
struct DicomWebUrl {
    std::string scheme;  ///< "http" or "https"
    std::string host;
    std::uint16_t port = 0;
    std::string path;    ///< without a trailing slash ("/dicom-web")

    /// Parses `url`; throws core::Error prefixed by `where` when it is not an http(s) URL with a
    /// host (user names and passwords belong in the node's settings, not in the URL).
    static DicomWebUrl parse(const std::string& url, const std::string& where);
    /// Throws as parse() does.
    static void check(const std::string& url, const std::string& where) { (void)parse(url, where); }
    /// The URL without a trailing slash, to which "/studies..." is appended.
    static std::string root(const std::string& url);
    /// A query parameter value percent-encoded, except RFC 3986's unreserved characters and
    /// what DICOM values use that a query may hold as is: the wildcards * and ?, the person
    /// name separator ^ and the list comma. (Orthanc's DICOMweb plugin does not decode
    /// percent-escapes, so "DOE%5EJ*" would match nothing there.)
    static std::string encode(const std::string& value);
};

}  // namespace hvx::dicom
