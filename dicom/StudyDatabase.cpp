#include "dicom/StudyDatabase.h"

#include <sqlite3.h>

#include <glm/geometric.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <thread>

#include "core/base/Error.h"
#include "dicom/PersonName.h"

namespace hvx::dicom {

namespace {
/// 1: the first schema; 2: instances.offline; 3: volumes (the volumes of a 4D series);
/// 4: series.warnings (what assembling the series found: assumed spacing, gaps...);
/// 5: series.refers_to (a SEG's or RTSTRUCT's image series).
constexpr std::int64_t kSchemaVersion = 5;
const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS patients (
  id INTEGER PRIMARY KEY, patient_id TEXT NOT NULL, name TEXT NOT NULL,
  birth_date TEXT, sex TEXT, UNIQUE(patient_id, name));
CREATE TABLE IF NOT EXISTS studies (
  id INTEGER PRIMARY KEY, uid TEXT NOT NULL UNIQUE,
  patient INTEGER NOT NULL REFERENCES patients(id) ON DELETE CASCADE,
  date TEXT, time TEXT, description TEXT, accession TEXT, modalities TEXT);
CREATE TABLE IF NOT EXISTS series (
  id INTEGER PRIMARY KEY, uid TEXT NOT NULL UNIQUE,
  study INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
  number INTEGER, description TEXT, modality TEXT, body_part TEXT,
  instance_count INTEGER NOT NULL DEFAULT 0, octree TEXT, warnings TEXT NOT NULL DEFAULT '',
  refers_to TEXT NOT NULL DEFAULT '');
CREATE TABLE IF NOT EXISTS instances (
  id INTEGER PRIMARY KEY, sop_uid TEXT NOT NULL UNIQUE,
  series INTEGER NOT NULL REFERENCES series(id) ON DELETE CASCADE,
  path TEXT NOT NULL, transfer_syntax TEXT, sop_class TEXT, instance_number INTEGER, file_size INTEGER,
  offline INTEGER NOT NULL DEFAULT 0);
CREATE TABLE IF NOT EXISTS volumes (
  series INTEGER NOT NULL REFERENCES series(id) ON DELETE CASCADE, number INTEGER NOT NULL,
  varying TEXT NOT NULL, octree TEXT, PRIMARY KEY(series, number));
CREATE INDEX IF NOT EXISTS instances_series ON instances(series);
CREATE INDEX IF NOT EXISTS series_study ON series(study);
CREATE INDEX IF NOT EXISTS studies_patient ON studies(patient);
CREATE INDEX IF NOT EXISTS studies_date ON studies(date);
)sql";

// A prepared statement, finalized on scope exit.
class Stmt {
public:
    Stmt(sqlite3* db, const char* sql) : db_(db) {
        if (sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) != SQLITE_OK)
            throw core::Error(std::string("study database: ") + sqlite3_errmsg(db));
    }
    ~Stmt() { sqlite3_finalize(s_); }
    Stmt(const Stmt&) = delete;
    Stmt& operator=(const Stmt&) = delete;
    Stmt& bind(int i, const std::string& v) {
        sqlite3_bind_text(s_, i, v.c_str(), int(v.size()), SQLITE_TRANSIENT);
        return *this;
    }
    Stmt& bind(int i, std::int64_t v) {
        sqlite3_bind_int64(s_, i, v);
        return *this;
    }
    bool step() {
        const int rc = sqlite3_step(s_);
        if (rc == SQLITE_ROW) return true;
        if (rc == SQLITE_DONE) return false;
        throw core::Error(std::string("study database: ") + sqlite3_errmsg(db_));
    }
    void reset() {
        sqlite3_reset(s_);
        sqlite3_clear_bindings(s_);
    }
    std::string text(int c) const {
        const auto* t = sqlite3_column_text(s_, c);
        return t ? reinterpret_cast<const char*>(t) : "";
    }
    std::int64_t integer(int c) const { return sqlite3_column_int64(s_, c); }

private:
    sqlite3* db_;
    sqlite3_stmt* s_ = nullptr;
};

// DICOM wildcards (* ?) to SQL LIKE (% _); plain text becomes a substring match.
std::string likePattern(const std::string& text) {
    std::string out;
    bool wildcard = false;
    for (char c : text) {
        if (c == '*') { out += '%'; wildcard = true; }
        else if (c == '?') { out += '_'; wildcard = true; }
        else if (c == '%' || c == '_' || c == '\\') { out += '\\'; out += c; }
        else out += c;
    }
    return wildcard ? out : "%" + out + "%";
}
}  // namespace

StudyDatabase::StudyDatabase(const std::string& path) : path_(path) {
    std::error_code ec;
    const auto parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                        nullptr) != SQLITE_OK) {
        const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
        sqlite3_close(db_);
        db_ = nullptr;
        throw core::Error(path + ": cannot open the study database (" + why + ")");
    }
    sqlite3_busy_timeout(db_, 5000);
    // Several jobs may open (and create) the file at once. Switching to WAL and creating the
    // schema take locks that SQLite refuses at once, without calling the busy handler, when two
    // connections would deadlock (each reading, each wanting to write); so opening retries.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    for (int attempt = 0;; ++attempt) {
        lastFailureBusy_ = false;
        try {
            exec("PRAGMA foreign_keys = ON;");
            exec("PRAGMA journal_mode = WAL;");
            transaction([&] { exec(kSchema); });
            migrate();
            return;
        } catch (const core::Error& e) {
            const int code = sqlite3_errcode(db_) & 0xff;
            const bool busy = lastFailureBusy_ || code == SQLITE_BUSY || code == SQLITE_LOCKED;
            if (busy && std::chrono::steady_clock::now() < deadline) {
                std::this_thread::sleep_for(std::chrono::milliseconds(2 + 3 * (attempt % 7)));
                continue;
            }
            sqlite3_close(db_);
            db_ = nullptr;
            throw core::Error(path + ": not a usable study database (" + e.what() + ")");
        }
    }
}

StudyDatabase::~StudyDatabase() { sqlite3_close(db_); }

std::string StudyDatabase::defaultPath() {
    if (const char* p = std::getenv("HOLOVOX_DB"); p && *p) return p;
    std::filesystem::path base;
    if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x) base = x;
    else if (const char* h = std::getenv("HOME"); h && *h) base = std::filesystem::path(h) / ".local/share";
    else base = std::filesystem::temp_directory_path();
    return (base / "holovox" / "studies.sqlite").string();
}

void StudyDatabase::migrate() {
    std::int64_t version = 0;
    {
        Stmt v(db_, "PRAGMA user_version;");
        if (v.step()) version = v.integer(0);
    }
    if (version > kSchemaVersion)
        throw core::Error("it was written by a newer Holovox (schema version " + std::to_string(version) + ", this one reads " +
                          std::to_string(kSchemaVersion) + ")");
    if (version >= kSchemaVersion) return;
    const auto hasColumn = [&](const char* table, const std::string& column) {
        Stmt cols(db_, (std::string("PRAGMA table_info(") + table + ");").c_str());
        while (cols.step())
            if (cols.text(1) == column) return true;
        return false;
    };
    // Version 1 (no user_version): instances had no offline flag; before 4, series no warnings.
    const bool hasOffline = hasColumn("instances", "offline"), hasWarnings = hasColumn("series", "warnings"),
               hasRefersTo = hasColumn("series", "refers_to");
    transaction([&] {
        if (!hasOffline) exec("ALTER TABLE instances ADD COLUMN offline INTEGER NOT NULL DEFAULT 0;");
        if (!hasWarnings) exec("ALTER TABLE series ADD COLUMN warnings TEXT NOT NULL DEFAULT '';");
        if (!hasRefersTo) exec("ALTER TABLE series ADD COLUMN refers_to TEXT NOT NULL DEFAULT '';");
        exec(("PRAGMA user_version = " + std::to_string(kSchemaVersion) + ";").c_str());
    });
}

void StudyDatabase::transaction(const std::function<void()>& body) {
    exec("BEGIN IMMEDIATE;");
    try {
        body();
        exec("COMMIT;");
    } catch (...) {
        exec("ROLLBACK;");
        throw;
    }
}

void StudyDatabase::exec(const char* sql) const {
    char* err = nullptr;
    if (const int rc = sqlite3_exec(db_, sql, nullptr, nullptr, &err); rc != SQLITE_OK) {
        lastFailureBusy_ = (rc & 0xff) == SQLITE_BUSY || (rc & 0xff) == SQLITE_LOCKED;
        const std::string why = err ? err : "unknown error";
        sqlite3_free(err);
        throw core::Error("study database: " + why);
    }
}

namespace {
/// Paths are kept absolute, so that a row still names its file from another working folder.
std::string absolutePath(const std::string& path) {
    std::error_code ec;
    const auto p = std::filesystem::absolute(path, ec);
    return ec ? path : p.lexically_normal().string();
}
}  // namespace

StudyDatabase::ImportStats StudyDatabase::addInstances(const std::vector<DicomInstance>& instances) {
    ImportStats stats;
    transaction([&] {
        Stmt patient(db_, "INSERT INTO patients(patient_id, name, birth_date, sex) VALUES(?1, ?2, ?3, ?4) "
                          "ON CONFLICT(patient_id, name) DO UPDATE SET birth_date = coalesce(nullif(?3, ''), birth_date), "
                          "sex = coalesce(nullif(?4, ''), sex) RETURNING id;");
        Stmt study(db_, "INSERT INTO studies(uid, patient, date, time, description, accession) VALUES(?1, ?2, ?3, ?4, ?5, ?6) "
                        "ON CONFLICT(uid) DO UPDATE SET date = coalesce(nullif(?3, ''), date) RETURNING id;");
        Stmt series(db_, "INSERT INTO series(uid, study, number, description, modality, body_part, refers_to) "
                         "VALUES(?1, ?2, ?3, ?4, ?5, ?6, ?7) ON CONFLICT(uid) DO UPDATE SET "
                         "refers_to = CASE WHEN refers_to = '' THEN excluded.refers_to ELSE refers_to END RETURNING id;");
        Stmt find(db_, "SELECT path FROM instances WHERE sop_uid = ?1;");
        // What a UID is already filed under: an instance naming another is a collision.
        Stmt studyOwner(db_, "SELECT p.patient_id, p.name FROM studies s JOIN patients p ON p.id = s.patient WHERE s.uid = ?1;");
        Stmt seriesOwner(db_, "SELECT st.uid FROM series se JOIN studies st ON st.id = se.study WHERE se.uid = ?1;");
        Stmt sopOwner(db_, "SELECT se.uid FROM instances i JOIN series se ON se.id = i.series WHERE i.sop_uid = ?1;");
        std::map<std::string, std::size_t> conflictCounts;  // sentence -> images
        std::map<std::string, std::pair<int, glm::dvec3>> inBatch;  // SOP UID -> instance number, first position
        auto refuse = [&](std::size_t index, const std::string& why) {
            stats.refused.push_back(index);
            ++conflictCounts[why];
        };
        Stmt put(db_, "INSERT INTO instances(sop_uid, series, path, transfer_syntax, sop_class, instance_number, file_size) "
                      "VALUES(?1, ?2, ?3, ?4, ?5, ?6, ?7) ON CONFLICT(sop_uid) DO UPDATE SET path = ?3, series = ?2, "
                      "transfer_syntax = ?4, file_size = ?7;");
        std::set<std::int64_t> touchedSeries, touchedStudies, grown;
        for (std::size_t index = 0; index < instances.size(); ++index) {
            const auto& in = instances[index];
            if (in.studyInstanceUid.empty() || in.seriesInstanceUid.empty() || in.sopInstanceUid.empty()) continue;
            const std::string who = in.patientName + " (" + in.patientId + ")";
            studyOwner.reset();
            studyOwner.bind(1, in.studyInstanceUid);
            if (studyOwner.step() && (studyOwner.text(0) != in.patientId || personNameKey(studyOwner.text(1)) != personNameKey(in.patientName))) {
                refuse(index, "study " + in.studyInstanceUid + " is filed under patient " + studyOwner.text(1) + " (" +
                                  studyOwner.text(0) + "), not " + who + " whom these images name (if the archive has "
                                  "corrected the study's patient since, remove the local study first: Remove study in "
                                  "the study browser, or holovox-cli remove-study " + in.studyInstanceUid + ")");
                continue;
            }
            seriesOwner.reset();
            seriesOwner.bind(1, in.seriesInstanceUid);
            if (seriesOwner.step() && seriesOwner.text(0) != in.studyInstanceUid) {
                refuse(index, "series " + in.seriesInstanceUid + " is filed under study " + seriesOwner.text(0) +
                                  ", not study " + in.studyInstanceUid + " of " + who + " that these images name");
                continue;
            }
            sopOwner.reset();
            sopOwner.bind(1, in.sopInstanceUid);
            if (sopOwner.step() && sopOwner.text(0) != in.seriesInstanceUid) {
                refuse(index, "their SOP Instance UIDs are filed in series " + sopOwner.text(0) + ", not series " +
                                  in.seriesInstanceUid + " of " + who + " that they name");
                continue;
            }
            // Two files of one SOP Instance UID: copies, unless their images differ.
            const glm::dvec3 at = in.frameGeometry.empty() ? glm::dvec3(0.0) : in.frame(0).position;
            if (const auto seen = inBatch.find(in.sopInstanceUid); seen != inBatch.end()) {
                if (seen->second.first != in.instanceNumber || glm::length(seen->second.second - at) > 1e-3) {
                    refuse(index, "they share their SOP Instance UID with another image of series " +
                                      in.seriesInstanceUid + " (other instance number or position)");
                    continue;
                }
            } else {
                inBatch[in.sopInstanceUid] = {in.instanceNumber, at};
            }
            patient.reset();
            patient.bind(1, in.patientId).bind(2, in.patientName).bind(3, in.patientBirthDate).bind(4, in.patientSex);
            patient.step();
            const auto patientId = patient.integer(0);
            while (patient.step()) {}
            study.reset();
            study.bind(1, in.studyInstanceUid).bind(2, patientId).bind(3, in.studyDate).bind(4, in.studyTime)
                .bind(5, in.studyDescription).bind(6, in.accessionNumber);
            study.step();
            const auto studyId = study.integer(0);
            while (study.step()) {}
            series.reset();
            series.bind(1, in.seriesInstanceUid).bind(2, studyId).bind(3, std::int64_t(in.seriesNumber))
                .bind(4, in.seriesDescription).bind(5, in.modality).bind(6, in.bodyPartExamined).bind(7, in.referencedSeriesUid);
            series.step();
            const auto seriesId = series.integer(0);
            while (series.step()) {}
            const std::string path = absolutePath(in.path);
            find.reset();
            find.bind(1, in.sopInstanceUid);
            if (find.step()) {
                if (find.text(0) == path) {
                    ++stats.unchanged;
                    continue;
                }
                ++stats.moved;
            } else {
                ++stats.added;
                grown.insert(seriesId);
            }
            put.reset();
            put.bind(1, in.sopInstanceUid).bind(2, seriesId).bind(3, path).bind(4, in.transferSyntaxUid)
                .bind(5, in.sopClassUid).bind(6, std::int64_t(in.instanceNumber)).bind(7, std::int64_t(in.fileSize));
            put.step();
            touchedSeries.insert(seriesId);
            touchedStudies.insert(studyId);
        }
        for (const auto& [why, n] : conflictCounts)
            stats.conflicts.push_back(std::to_string(n) + " image(s) refused, never filed: " + why +
                                      " (a UID collision; the images already filed stay as they were)");
        // An octree built before a series gained images holds fewer than the series: forgotten,
        // so that opening the series builds it again (a stale one had opened, interpolated
        // across slices that had since arrived).
        Stmt stale(db_, "UPDATE series SET octree = NULL WHERE id = ?1;");
        Stmt staleVolumes(db_, "UPDATE volumes SET octree = NULL WHERE series = ?1;");
        for (auto id : grown) {
            stale.reset();
            stale.bind(1, id);
            stale.step();
            staleVolumes.reset();
            staleVolumes.bind(1, id);
            staleVolumes.step();
        }
        Stmt count(db_, "UPDATE series SET instance_count = (SELECT count(*) FROM instances WHERE series = ?1) WHERE id = ?1;");
        for (auto id : touchedSeries) {
            count.reset();
            count.bind(1, id);
            count.step();
        }
        Stmt mods(db_, "UPDATE studies SET modalities = (SELECT group_concat(m, '\\') FROM "
                       "(SELECT DISTINCT modality AS m FROM series WHERE study = ?1 AND modality != '' ORDER BY m)) "
                       "WHERE id = ?1;");
        for (auto id : touchedStudies) {
            mods.reset();
            mods.bind(1, id);
            mods.step();
        }
    });
    return stats;
}

std::vector<DicomInstance> StudyDatabase::ImportStats::accepted(const std::vector<DicomInstance>& instances) const {
    const std::set<std::size_t> out(refused.begin(), refused.end());
    std::vector<DicomInstance> kept;
    for (std::size_t i = 0; i < instances.size(); ++i)
        if (!out.count(i)) kept.push_back(instances[i]);
    return kept;
}

StudyDatabase::FileCheck StudyDatabase::checkFiles() {
    std::vector<std::pair<std::int64_t, bool>> changed;  // id, offline now
    FileCheck check;
    {
        Stmt all(db_, "SELECT id, path, offline FROM instances;");
        std::error_code ec;
        while (all.step()) {
            const bool offline = !std::filesystem::exists(all.text(1), ec);
            const bool was = all.integer(2) != 0;
            if (offline) ++check.offline;
            if (offline != was) changed.emplace_back(all.integer(0), offline);
            if (was && !offline) ++check.backOnline;
        }
    }
    if (changed.empty()) return check;
    transaction([&] {
        Stmt set(db_, "UPDATE instances SET offline = ?2 WHERE id = ?1;");
        for (const auto& [id, offline] : changed) {
            set.reset();
            set.bind(1, id);
            set.bind(2, std::int64_t(offline ? 1 : 0));
            set.step();
        }
    });
    return check;
}

std::size_t StudyDatabase::offlineCount() const {
    Stmt s(db_, "SELECT count(*) FROM instances WHERE offline != 0;");
    return s.step() ? std::size_t(s.integer(0)) : 0;
}

StudyDatabase::PruneResult StudyDatabase::prune() {
    std::vector<std::int64_t> gone;
    PruneResult result;
    {
        Stmt all(db_, "SELECT id, path FROM instances;");
        std::error_code ec;
        // A file is taken as deleted only when its folder is there and holds something: an
        // unmounted disk leaves its mount point behind, empty, with every file "missing".
        std::map<std::filesystem::path, bool> folderThere;
        while (all.step()) {
            const std::filesystem::path file = all.text(1);
            if (std::filesystem::exists(file, ec)) continue;
            const auto folder = file.parent_path();
            auto it = folderThere.find(folder);
            if (it == folderThere.end())
                it = folderThere.emplace(folder, std::filesystem::is_directory(folder, ec) &&
                                                     !std::filesystem::is_empty(folder, ec) && !ec).first;
            if (it->second) gone.push_back(all.integer(0));
            else ++result.kept;
        }
    }
    transaction([&] {
        Stmt del(db_, "DELETE FROM instances WHERE id = ?1;");
        for (auto id : gone) {
            del.reset();
            del.bind(1, id);
            del.step();
        }
        exec("UPDATE series SET instance_count = (SELECT count(*) FROM instances WHERE series = series.id);"
             "DELETE FROM series WHERE instance_count = 0;"
             "DELETE FROM studies WHERE id NOT IN (SELECT study FROM series);"
             "DELETE FROM patients WHERE id NOT IN (SELECT patient FROM studies);");
    });
    result.removed = gone.size();
    return result;
}

StudyDatabase::RemovedStudy StudyDatabase::removeStudy(const std::string& studyUid) {
    RemovedStudy removed;
    transaction([&] {
        Stmt study(db_, "SELECT st.id, p.name, p.patient_id FROM studies st JOIN patients p ON p.id = st.patient "
                        "WHERE st.uid = ?1;");
        study.bind(1, studyUid);
        if (!study.step()) throw core::Error("study " + studyUid + " is not in the study database");
        const std::int64_t id = study.integer(0);
        removed.patient = study.text(1) + " (" + study.text(2) + ")";
        while (study.step()) {}
        Stmt files(db_, "SELECT i.path, se.uid, i.sop_uid FROM instances i JOIN series se ON se.id = i.series "
                        "WHERE se.study = ?1 ORDER BY i.path;");
        files.bind(1, id);
        while (files.step()) removed.files.push_back({files.text(0), files.text(1), files.text(2)});
        Stmt series(db_, "SELECT uid FROM series WHERE study = ?1 ORDER BY uid;");
        series.bind(1, id);
        while (series.step()) removed.series.push_back(series.text(0));
        Stmt octrees(db_, "SELECT octree FROM series WHERE study = ?1 AND octree IS NOT NULL AND octree != '' UNION "
                          "SELECT v.octree FROM volumes v JOIN series se ON se.id = v.series WHERE se.study = ?1 "
                          "AND v.octree IS NOT NULL AND v.octree != '';");
        octrees.bind(1, id);
        while (octrees.step()) removed.octrees.push_back(octrees.text(0));
        Stmt del(db_, "DELETE FROM studies WHERE id = ?1;");  // series, instances and volumes cascade
        del.bind(1, id);
        del.step();
        exec("DELETE FROM patients WHERE id NOT IN (SELECT patient FROM studies);");
    });
    return removed;
}

std::vector<std::string> StudyDatabase::recordedOctrees() const {
    Stmt s(db_, "SELECT octree FROM series WHERE octree IS NOT NULL AND octree != '' UNION "
                "SELECT octree FROM volumes WHERE octree IS NOT NULL AND octree != '';");
    std::vector<std::string> paths;
    while (s.step()) paths.push_back(s.text(0));
    return paths;
}

std::vector<StudyRow> StudyDatabase::findStudies(const StudyQuery& q) const {
    Stmt s(db_,
           "SELECT p.name, p.patient_id, p.birth_date, p.sex, st.uid, st.date, st.time, st.description, st.accession, "
           "coalesce(st.modalities, ''), (SELECT count(*) FROM series WHERE study = st.id) "
           "FROM studies st JOIN patients p ON p.id = st.patient "
           "WHERE (?1 = '' OR p.name LIKE ?2 ESCAPE '\\' OR p.patient_id LIKE ?2 ESCAPE '\\') "
           "AND (?3 = '' OR st.date >= ?3) AND (?4 = '' OR st.date <= ?4) "
           "AND (?5 = '' OR EXISTS (SELECT 1 FROM series WHERE study = st.id AND modality = ?5)) "
           "ORDER BY st.date DESC, st.time DESC, p.name;");
    s.bind(1, q.text).bind(2, likePattern(q.text)).bind(3, q.dateFrom).bind(4, q.dateTo).bind(5, q.modality);
    std::vector<StudyRow> rows;
    while (s.step()) {
        StudyRow r;
        r.patientName = s.text(0);
        r.patientId = s.text(1);
        r.patientBirthDate = s.text(2);
        r.patientSex = s.text(3);
        r.studyUid = s.text(4);
        r.date = s.text(5);
        r.time = s.text(6);
        r.description = s.text(7);
        r.accession = s.text(8);
        r.modalities = s.text(9);
        r.seriesCount = int(s.integer(10));
        rows.push_back(std::move(r));
    }
    return rows;
}

namespace {
const char* kSeriesColumns =
    "SELECT se.uid, st.uid, se.modality, se.description, se.body_part, coalesce(se.octree, ''), se.number, "
    "se.instance_count, se.warnings, se.refers_to FROM series se JOIN studies st ON st.id = se.study ";

SeriesRow seriesRow(const Stmt& s) {
    SeriesRow r;
    r.seriesUid = s.text(0);
    r.studyUid = s.text(1);
    r.modality = s.text(2);
    r.description = s.text(3);
    r.bodyPart = s.text(4);
    r.octreePath = s.text(5);
    r.number = int(s.integer(6));
    const std::string warnings = s.text(8);
    for (std::size_t at = 0; at < warnings.size();) {
        const auto end = std::min(warnings.find('\n', at), warnings.size());
        r.warnings.push_back(warnings.substr(at, end - at));
        at = end + 1;
    }
    r.instanceCount = int(s.integer(7));
    r.refersTo = s.text(9);
    return r;
}
}  // namespace

std::vector<SeriesRow> StudyDatabase::seriesOfStudy(const std::string& studyUid) const {
    Stmt s(db_, (std::string(kSeriesColumns) + "WHERE st.uid = ?1 ORDER BY se.number, se.uid;").c_str());
    s.bind(1, studyUid);
    std::vector<SeriesRow> rows;
    while (s.step()) rows.push_back(seriesRow(s));
    return rows;
}

bool StudyDatabase::findSeries(const std::string& seriesUid, SeriesRow& out) const {
    Stmt s(db_, (std::string(kSeriesColumns) + "WHERE se.uid = ?1;").c_str());
    s.bind(1, seriesUid);
    if (!s.step()) return false;
    out = seriesRow(s);
    return true;
}

std::map<std::string, std::string> StudyDatabase::onlineInstancesOfSeries(const std::string& seriesUid) const {
    Stmt s(db_, "SELECT i.sop_uid, i.path FROM instances i JOIN series se ON se.id = i.series "
                "WHERE se.uid = ?1 AND i.offline = 0;");
    s.bind(1, seriesUid);
    std::map<std::string, std::string> out;
    while (s.step()) out[s.text(0)] = s.text(1);
    return out;
}

std::vector<std::string> StudyDatabase::filesOfSeries(const std::string& seriesUid) const {
    Stmt s(db_, "SELECT i.path FROM instances i JOIN series se ON se.id = i.series WHERE se.uid = ?1 "
                "ORDER BY i.instance_number, i.path;");
    s.bind(1, seriesUid);
    std::vector<std::string> files;
    while (s.step()) files.push_back(s.text(0));
    return files;
}

std::set<std::string> StudyDatabase::indexedPaths(const std::string& dbPath, const std::vector<std::string>& paths) {
    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(dbPath.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
    std::unique_ptr<sqlite3, int (*)(sqlite3*)> closer(db, sqlite3_close);
    std::set<std::string> out;
    try {
        if (rc != SQLITE_OK) throw core::Error(db ? sqlite3_errmsg(db) : "out of memory");
        sqlite3_busy_timeout(db, 5000);
        Stmt s(db, "SELECT 1 FROM instances WHERE path = ?1 LIMIT 1;");
        for (const auto& p : paths) {
            s.reset();
            if (s.bind(1, p).step()) out.insert(p);
        }
    } catch (const core::Error& e) {
        throw core::Error(dbPath + ": cannot read that study database (" + e.what() + ")");
    }
    return out;
}

bool StudyDatabase::setSeriesOctree(const std::string& seriesUid, const std::string& octreePath) {
    Stmt s(db_, "UPDATE series SET octree = ?2 WHERE uid = ?1;");
    s.bind(1, seriesUid).bind(2, absolutePath(octreePath));
    s.step();
    return sqlite3_changes(db_) > 0;
}

void StudyDatabase::setSeriesWarnings(const std::string& seriesUid, const std::vector<std::string>& warnings) {
    std::string all;
    for (const auto& w : warnings) all += (all.empty() ? "" : "\n") + w;
    Stmt up(db_, "UPDATE series SET warnings = ?2 WHERE uid = ?1;");
    up.bind(1, seriesUid).bind(2, all);
    up.step();
}

void StudyDatabase::setSeriesVolumes(const std::string& seriesUid, const std::vector<std::string>& varying) {
    transaction([&] {
        // A volume keeps its octree while what it is stays the same.
        Stmt up(db_,
                "INSERT INTO volumes(series, number, varying) SELECT id, ?2, ?3 FROM series WHERE uid = ?1 "
                "ON CONFLICT(series, number) DO UPDATE SET varying = excluded.varying, "
                "octree = CASE WHEN volumes.varying = excluded.varying THEN volumes.octree ELSE NULL END;");
        for (std::size_t i = 0; i < varying.size(); ++i) {
            up.reset();
            up.bind(1, seriesUid).bind(2, std::int64_t(i + 1)).bind(3, varying[i]);
            up.step();
        }
        Stmt drop(db_, "DELETE FROM volumes WHERE number > ?2 AND series = (SELECT id FROM series WHERE uid = ?1);");
        drop.bind(1, seriesUid).bind(2, std::int64_t(varying.size()));
        drop.step();
    });
}

std::vector<VolumeRow> StudyDatabase::volumesOfSeries(const std::string& seriesUid) const {
    Stmt s(db_, "SELECT v.number, v.varying, coalesce(v.octree, '') FROM volumes v JOIN series se ON se.id = v.series "
                "WHERE se.uid = ?1 ORDER BY v.number;");
    s.bind(1, seriesUid);
    std::vector<VolumeRow> out;
    while (s.step()) out.push_back({int(s.integer(0)), s.text(1), s.text(2)});
    return out;
}

bool StudyDatabase::setVolumeOctree(const std::string& seriesUid, int number, const std::string& octreePath) {
    Stmt s(db_, "UPDATE volumes SET octree = ?3 WHERE number = ?2 AND series = (SELECT id FROM series WHERE uid = ?1);");
    s.bind(1, seriesUid).bind(2, std::int64_t(number)).bind(3, absolutePath(octreePath));
    s.step();
    return sqlite3_changes(db_) > 0;
}

std::size_t StudyDatabase::instanceCount() const {
    Stmt s(db_, "SELECT count(*) FROM instances;");
    s.step();
    return std::size_t(s.integer(0));
}

}  // namespace hvx::dicom
