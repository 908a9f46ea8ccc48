#include "dicom/LibraryVersions.h"

#include <curl/curl.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <openjpeg.h>
#include <openssl/crypto.h>
#include <sqlite3.h>

#include <glm/detail/setup.hpp>

#include "core/image/ImageWriter.h"
#include "core/octree/BrickCodec.h"
#include "core/volume/VtkImageSource.h"

namespace hvx::dicom {

namespace {
/// "zstd 1.5.4, LZ4 1.9.4" as (name, version) pairs.
void split(const std::string& list, std::vector<std::pair<std::string, std::string>>& out) {
    std::size_t start = 0;
    while (start < list.size()) {
        const std::size_t end = std::min(list.find(", ", start), list.size());
        const std::string item = list.substr(start, end - start);
        const std::size_t space = item.rfind(' ');
        out.emplace_back(item.substr(0, space), space == std::string::npos ? std::string() : item.substr(space + 1));
        start = end + 2;
    }
}
}  // namespace

std::vector<std::pair<std::string, std::string>> LibraryVersions::all() {
    std::vector<std::pair<std::string, std::string>> out{
        {"DCMTK", OFFIS_DCMTK_VERSION_STRING},
        {"libcurl", curl_version_info(CURLVERSION_NOW)->version},
        {"OpenSSL", OpenSSL_version(OPENSSL_VERSION_STRING)},
        {"SQLite", sqlite3_libversion()},
        {"OpenJPEG", opj_version()},
    };
    split(core::VtkImageSource::libraryVersion(), out);
    split(core::BrickCodec::libraryVersions(), out);
    split(core::ImageWriter::libraryVersions(), out);
    out.emplace_back("GLM", std::to_string(GLM_VERSION_MAJOR) + "." + std::to_string(GLM_VERSION_MINOR) + "." +
                                std::to_string(GLM_VERSION_PATCH));
    return out;
}

}  // namespace hvx::dicom
