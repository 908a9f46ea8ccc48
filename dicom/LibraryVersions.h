#pragma once
#include <string>
#include <utility>
#include <vector>

namespace hvx::dicom {

/// The libraries Holovox is built on, as linked, for `holovox-cli version` and Help → About:
/// DCMTK, libcurl, OpenSSL, SQLite, OpenJPEG, and those of core's rooms (VTK, zstd, LZ4, xxHash,
/// OpenEXR, libpng; GLM's version from its header).
class LibraryVersions {
public:
    /// (library, version) pairs, in the order above.
    static std::vector<std::pair<std::string, std::string>> all();
};

}  // namespace hvx::dicom
