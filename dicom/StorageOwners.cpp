#include "dicom/StorageOwners.h"

#include <filesystem>
#include <fstream>
#include <mutex>

namespace fs = std::filesystem;

namespace hvx::dicom {

namespace {
std::string absolute(const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    return ec ? path : p.string();
}

std::vector<std::string> listed(const std::string& storageDir) {
    std::vector<std::string> out;
    std::ifstream in(fs::path(storageDir) / StorageOwners::kListName);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) out.push_back(line);
    return out;
}
}  // namespace

void StorageOwners::add(const std::string& storageDir, const std::string& dbPath) {
    static std::mutex mutex;  // two retrieves of one process at once add one line
    std::lock_guard lock(mutex);
    if (storageDir.empty()) return;
    const std::string me = absolute(dbPath);
    for (const auto& d : listed(storageDir))
        if (d == me) return;
    std::error_code ec;
    fs::create_directories(storageDir, ec);
    std::ofstream out(fs::path(storageDir) / kListName, std::ios::app);
    out << me << '\n';  // one short append: another process's line is not torn
}

std::vector<std::string> StorageOwners::othersThan(const std::string& storageDir, const std::string& dbPath) {
    const std::string me = absolute(dbPath);
    std::vector<std::string> out;
    if (storageDir.empty()) return out;
    std::error_code ec;
    for (const auto& d : listed(storageDir))
        if (d != me && absolute(d) != me && fs::is_regular_file(d, ec)) out.push_back(d);
    return out;
}

}  // namespace hvx::dicom
