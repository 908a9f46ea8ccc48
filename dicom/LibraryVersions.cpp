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

std::vector<std::pair<std::string, std::string>> LibraryVersions::all() {
    std::vector<std::pair<std::string, std::string>> out{
        {"DCMTK", OFFIS_DCMTK_VERSION_STRING},
        {"libcurl", curl_version_info(CURLVERSION_NOW)->version},
        {"OpenSSL", OpenSSL_version(OPENSSL_VERSION_STRING)},
        {"SQLite", sqlite3_libversion()},
        {"OpenJPEG", opj_version()},
    };
    out.emplace_back("VTK", core::VtkImageSource::libraryVersion());
    for (auto& v : core::BrickCodec::libraryVersions()) out.push_back(std::move(v));
    for (auto& v : core::ImageWriter::libraryVersions()) out.push_back(std::move(v));
    out.emplace_back("GLM", std::to_string(GLM_VERSION_MAJOR) + "." + std::to_string(GLM_VERSION_MINOR) + "." +
                                std::to_string(GLM_VERSION_PATCH));
    return out;
}

}  // namespace hvx::dicom
