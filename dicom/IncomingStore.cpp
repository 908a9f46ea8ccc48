#include "dicom/IncomingStore.h"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <stdio.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/UidPath.h"

namespace fs = std::filesystem;

namespace hvx::dicom {

namespace {
/// One counter for the whole process: two stores (two retrieves at once) never share a name.
std::atomic<unsigned long> processCounter{0};

void fsyncPath(const std::string& path, int flags) {
    const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

/// Where the dataset begins: after the preamble and the File Meta Information (group 0002,
/// explicit VR little endian by the standard), or 0 when the file has no preamble.
std::uint64_t datasetOffset(std::ifstream& in) {
    char head[132];
    in.seekg(0);
    if (!in.read(head, sizeof head) || std::memcmp(head + 128, "DICM", 4) != 0) return 0;
    std::uint64_t at = 132;
    for (;;) {
        unsigned char e[12];
        in.seekg(std::streamoff(at));
        if (!in.read(reinterpret_cast<char*>(e), 8)) break;
        if ((e[0] | e[1] << 8) != 0x0002) break;
        const std::string vr(reinterpret_cast<char*>(e + 4), 2);
        if (vr == "OB" || vr == "OW" || vr == "UN" || vr == "SQ" || vr == "UT" || vr == "OF") {
            if (!in.read(reinterpret_cast<char*>(e + 8), 4)) break;
            at += 12 + (std::uint64_t(e[8]) | std::uint64_t(e[9]) << 8 | std::uint64_t(e[10]) << 16 |
                        std::uint64_t(e[11]) << 24);
        } else {
            at += 8 + (std::uint64_t(e[6]) | std::uint64_t(e[7]) << 8);
        }
    }
    in.clear();
    return at;
}

/// The same instance content: the same dataset bytes. The File Meta Information is not
/// compared: it names the application and AE that wrote the file, which differ between a C-GET,
/// a C-MOVE and a WADO-RS of the same instance.
bool sameDataset(const std::string& a, const std::string& b) {
    std::error_code ec;
    std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
    const std::uint64_t oa = datasetOffset(fa), ob = datasetOffset(fb);
    const auto sa = fs::file_size(a, ec), sb = ec ? 0 : fs::file_size(b, ec);
    if (ec || sa < oa || sb < ob || sa - oa != sb - ob) return false;
    fa.seekg(std::streamoff(oa));
    fb.seekg(std::streamoff(ob));
    char x[65536], y[65536];
    while (fa && fb) {
        fa.read(x, sizeof x);
        fb.read(y, sizeof y);
        if (fa.gcount() != fb.gcount() || std::memcmp(x, y, std::size_t(fa.gcount())) != 0) return false;
    }
    return !fa && !fb;
}

/// rename() that never replaces: EEXIST when the target is there.
int renameNoReplace(const std::string& from, const std::string& to) {
    return ::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE);
}
}  // namespace

IncomingStore::IncomingStore(std::string storageDir, std::uint64_t minFreeBytes)
    : dir_(std::move(storageDir)), minFreeBytes_(minFreeBytes) {
    std::error_code ec;
    fs::create_directories(fs::path(dir_) / kIncomingFolder, ec);
    if (ec) throw core::Error(dir_ + ": cannot create the storage folder (" + ec.message() + ")");
}

std::uint64_t IncomingStore::freeBytes() const {
    struct statvfs s {};
    if (::statvfs(dir_.c_str(), &s) != 0) return 0;
    return std::uint64_t(s.f_bavail) * s.f_frsize;
}

std::string IncomingStore::temporaryPath() {
    int fd = -1;
    std::string path = temporaryFile(fd);
    ::close(fd);
    return path;
}

std::string IncomingStore::temporaryFile(int& fd) {
    if (minFreeBytes_ > 0) {
        const std::uint64_t free = freeBytes();
        if (free < minFreeBytes_)
            throw core::Error(dir_ + ": only " + std::to_string(free >> 20) + " MiB free; Holovox keeps " +
                              std::to_string(minFreeBytes_ >> 20) + " MiB free and takes no more instances");
    }
    thread_local std::mt19937_64 random(std::random_device{}());
    for (int attempt = 0; attempt < 100; ++attempt) {
        char name[96];
        std::snprintf(name, sizeof name, "rx-%d-%lu-%016llx.part", int(::getpid()), ++processCounter,
                      static_cast<unsigned long long>(random()));
        const std::string path = (fs::path(dir_) / kIncomingFolder / name).string();
        // Created here, exclusively and without following a link, so the name is ours alone.
        fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
        if (fd >= 0) return path;
        if (errno != EEXIST)
            throw core::Error(dir_ + ": cannot create a file for a received instance (" + std::strerror(errno) + ")");
    }
    throw core::Error(dir_ + ": cannot find a free name for a received instance");
}

DicomInstance IncomingStore::finalize(const std::string& temporary) {
    Placed placed = place(temporary);
    flushFolder(placed.folder);
    return std::move(placed.instance);
}

std::string IncomingStore::placeOf(const std::string& storageDir, const std::string& studyUid,
                                   const std::string& seriesUid, const std::string& sopUid) {
    return (fs::path(storageDir) / UidPath::component(studyUid) / UidPath::component(seriesUid) /
            (UidPath::component(sopUid) + ".dcm"))
        .string();
}

void IncomingStore::flushFolder(const std::string& folder) { fsyncPath(folder, O_RDONLY | O_DIRECTORY); }

IncomingStore::Placed IncomingStore::place(const std::string& temporary) {
    DicomInstance in;
    try {
        if (DicomHeaderReader::read(temporary, in) != DicomHeaderReader::Kind::Dicom)
            throw core::Error(temporary + ": received object is not DICOM");
    } catch (...) {
        std::remove(temporary.c_str());
        throw;
    }
    const fs::path target = placeOf(dir_, in.studyInstanceUid, in.seriesInstanceUid, in.sopInstanceUid);
    const fs::path folder = target.parent_path();
    std::error_code ec;
    if (fs::create_directories(folder, ec)) {  // new folders: their names are on disk too
        fsyncPath(folder.parent_path().string(), O_RDONLY | O_DIRECTORY);
        fsyncPath(dir_, O_RDONLY | O_DIRECTORY);
    }
    fsyncPath(temporary, O_RDONLY);  // the bytes are on disk before the name points at them
    if (!ec && renameNoReplace(temporary, target.string()) == 0) {
        in.path = target.string();
        return Placed{std::move(in), folder.string()};  // the name is on disk once the folder is flushed
    }
    if (!ec && errno == EEXIST) {
        if (sameDataset(temporary, target.string())) {  // the same instance again: nothing to do
            std::remove(temporary.c_str());
            in.path = target.string();
            return Placed{std::move(in), folder.string()};  // (another thread's rename may not be flushed yet)
        }
        // Another object under the same SOP Instance UID: never replace what is stored.
        const fs::path aside = fs::path(dir_) / kConflictsFolder;
        fs::create_directories(aside, ec);
        const fs::path kept = aside / (UidPath::component(in.sopInstanceUid) + "-" + fs::path(temporary).stem().string() + ".dcm");
        if (!ec && std::rename(temporary.c_str(), kept.c_str()) == 0)
            throw core::Error("instance " + in.sopInstanceUid + " arrived again with different content: the stored one is "
                              "kept, the new one set aside as " + kept.string());
    }
    std::remove(temporary.c_str());
    throw core::Error(target.string() + ": cannot store the received instance");
}

}  // namespace hvx::dicom
