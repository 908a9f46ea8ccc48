#include "dicom/IncomingStore.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/UidPath.h"

namespace fs = std::filesystem;

namespace hvx::dicom {

IncomingStore::IncomingStore(std::string storageDir) : dir_(std::move(storageDir)) {
    std::error_code ec;
    fs::create_directories(fs::path(dir_) / ".incoming", ec);
    if (ec) throw core::Error(dir_ + ": cannot create the storage folder (" + ec.message() + ")");
}

std::string IncomingStore::temporaryPath() {
    return (fs::path(dir_) / ".incoming" /
            ("rx-" + std::to_string(::getpid()) + "-" + std::to_string(++counter_) + ".part"))
        .string();
}

DicomInstance IncomingStore::finalize(const std::string& temporary) {
    DicomInstance in;
    try {
        if (DicomHeaderReader::read(temporary, in) != DicomHeaderReader::Kind::Dicom)
            throw core::Error(temporary + ": received object is not DICOM");
    } catch (...) {
        std::remove(temporary.c_str());
        throw;
    }
    const fs::path folder = fs::path(dir_) / UidPath::component(in.studyInstanceUid) /
                            UidPath::component(in.seriesInstanceUid);
    std::error_code ec;
    fs::create_directories(folder, ec);
    const fs::path target = folder / (UidPath::component(in.sopInstanceUid) + ".dcm");
    if (ec || std::rename(temporary.c_str(), target.c_str()) != 0) {
        std::remove(temporary.c_str());
        throw core::Error(target.string() + ": cannot store the received instance");
    }
    in.path = target.string();
    return in;
}

}  // namespace hvx::dicom
