#include "dicom/StorageOwners.h"

#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <mutex>

#include "core/base/Error.h"

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

std::set<std::string> StorageOwners::indexedIn(const std::string& dbPath, const std::vector<std::string>& paths) {
    sqlite3* db = nullptr;
    const auto fail = [&](const std::string& why) {
        const std::string text = dbPath + ": cannot read that study database (" + why + ")";
        sqlite3_close(db);
        return core::Error(text);
    };
    if (sqlite3_open_v2(dbPath.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
        throw fail(db ? sqlite3_errmsg(db) : "out of memory");
    sqlite3_busy_timeout(db, 5000);
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT 1 FROM instances WHERE path = ?1 LIMIT 1;", -1, &s, nullptr) != SQLITE_OK)
        throw fail(sqlite3_errmsg(db));
    std::set<std::string> out;
    for (const auto& p : paths) {
        sqlite3_reset(s);
        sqlite3_bind_text(s, 1, p.c_str(), int(p.size()), SQLITE_TRANSIENT);
        const int rc = sqlite3_step(s);
        if (rc == SQLITE_ROW) out.insert(p);
        else if (rc != SQLITE_DONE) {
            const std::string why = sqlite3_errmsg(db);
            sqlite3_finalize(s);
            throw fail(why);
        }
    }
    sqlite3_finalize(s);
    sqlite3_close(db);
    return out;
}

}  // namespace hvx::dicom
