#pragma once
#include <cstdint>
#include <memory>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "dicom/DicomInstance.h"

struct sqlite3;

namespace hvx::dicom {

/// Filters of the study browser. Empty fields match everything. `text` matches patient name or
/// patient ID, case-insensitively, with DICOM wildcards (* and ?) or as a substring.
struct StudyQuery {
    std::string text;
    std::string dateFrom;  ///< YYYYMMDD, inclusive
    std::string dateTo;    ///< YYYYMMDD, inclusive
    std::string modality;  ///< e.g. "CT": studies with at least one series of it
};

/// One study as the browser lists it, with its patient.
struct StudyRow {
    std::string patientName, patientId, patientBirthDate, patientSex;
    std::string studyUid, date, time, description, accession, modalities;
    int seriesCount = 0;
};

/// One volume of a 4D series (a series whose images split into several volumes).
struct VolumeRow {
    int number = 0;        ///< 1-based, in the order import lists them (build-series --volume N)
    std::string varying;   ///< what tells it apart: "echo 2 (TE 20 ms)", "b 1000 (...)", "time 3"
    std::string octreePath;
};

/// One series of a study.
struct SeriesRow {
    std::string seriesUid, studyUid, modality, description, bodyPart, octreePath;
    int number = 0;
    int instanceCount = 0;
    std::vector<std::string> warnings;  ///< what assembling the series found (assumed spacing, gaps...)
    std::string refersTo;  ///< a SEG's or RTSTRUCT's image series (its UID), empty otherwise
};

/// The local index of imported DICOM: patients → studies → series → instances, in one SQLite
/// file (schema version 5, WAL journal). Importing the same files again changes nothing; files
/// that cannot be reached are marked offline by checkFiles(), and rows are deleted only by an
/// explicit prune().
///
/// Threading: one thread at a time per object (open one object per thread if needed; SQLite
/// serialises writers across connections).
class StudyDatabase {
public:
    /// Opens or creates the database file (and its folder); throws core::Error naming it.
    explicit StudyDatabase(const std::string& path);
    ~StudyDatabase();
    StudyDatabase(const StudyDatabase&) = delete;
    StudyDatabase& operator=(const StudyDatabase&) = delete;

    /// $HOLOVOX_DB, else $XDG_DATA_HOME/holovox/studies.sqlite, else ~/.local/share/holovox/...
    static std::string defaultPath();

    struct ImportStats {
        std::size_t added = 0;      ///< instances new to the database
        std::size_t unchanged = 0;  ///< already known, same file
        std::size_t moved = 0;      ///< known SOP instance now found at another path
        /// Indices (into the instances given) refused as identity conflicts, none filed.
        std::vector<std::size_t> refused;
        /// One sentence per conflict: a study UID of another patient, a series UID of another
        /// study, a SOP Instance UID of another series, or of another image in this batch.
        std::vector<std::string> conflicts;
        /// The instances given less those refused (what may be stacked into volumes).
        std::vector<DicomInstance> accepted(const std::vector<DicomInstance>& instances) const;
    };
    /// Adds instances (and their patients, studies, series) in one transaction. A UID already
    /// filed under another patient, study or series (a UID collision, as a faulty anonymiser
    /// makes) refuses the instance, named in `conflicts`: one patient's image is never filed
    /// under another patient, study or series. Paths are kept absolute.
    ImportStats addInstances(const std::vector<DicomInstance>& instances);
    struct FileCheck {
        std::size_t offline = 0;     ///< instances whose files cannot be reached now
        std::size_t backOnline = 0;  ///< instances that were offline and are reachable again
    };
    /// Marks the instances whose files cannot be reached as offline, and those reachable again
    /// as online. Never deletes a row: an unmounted or renamed storage folder loses nothing.
    FileCheck checkFiles();
    struct PruneResult {
        std::size_t removed = 0;  ///< rows of files deleted from a folder that still exists
        std::size_t kept = 0;     ///< rows kept because the file's folder itself is missing
    };
    /// Deletes the instances whose files were deleted (the file is missing but its folder is
    /// there and not empty), then empty series, studies and patients. A file whose folder is
    /// missing or empty is taken as unreachable (an unmounted disk leaves an empty mount point;
    /// a renamed folder), kept and counted.
    PruneResult prune();
    /// What removeStudy() took out of the index.
    struct RemovedStudy {
        struct File {
            std::string path, seriesUid, sopUid;  ///< as indexed
        };
        std::string patient;               ///< "NAME (ID)"
        std::vector<std::string> series;   ///< the study's Series Instance UIDs
        std::vector<File> files;           ///< the study's instances
        std::vector<std::string> octrees;  ///< the octrees recorded for its series and volumes
    };
    /// Removes a study from the index: its series, instances and volumes, and its patient when
    /// no other study is left, in one transaction. Deletes no file (the caller deletes what is
    /// its own). Throws core::Error naming an unknown study.
    RemovedStudy removeStudy(const std::string& studyUid);
    /// Of `paths`, those the database file at `dbPath` indexes as instances, read without changing
    /// it (read-only, no migration): another database sharing a storage folder (StorageOwners).
    /// Throws core::Error naming that database when it cannot be read.
    static std::set<std::string> indexedPaths(const std::string& dbPath, const std::vector<std::string>& paths);
    /// Every octree path recorded for a series or a volume.
    std::vector<std::string> recordedOctrees() const;
    /// Instances marked offline by the last checkFiles().
    std::size_t offlineCount() const;

    std::vector<StudyRow> findStudies(const StudyQuery& query) const;
    std::vector<SeriesRow> seriesOfStudy(const std::string& studyUid) const;
    /// The series, if known (octreePath empty when none was built).
    bool findSeries(const std::string& seriesUid, SeriesRow& out) const;
    /// SOP Instance UID → file path of a series' instances that are not marked offline.
    std::map<std::string, std::string> onlineInstancesOfSeries(const std::string& seriesUid) const;
    /// File paths of a series' instances, ordered by instance number.
    std::vector<std::string> filesOfSeries(const std::string& seriesUid) const;
    /// Records the octree built for a series; false when the series is not in the index (removed
    /// while its octree was built), and nothing is recorded.
    bool setSeriesOctree(const std::string& seriesUid, const std::string& octreePath);
    /// Records the volumes a series splits into (what varies, in order); a series of one volume
    /// has none. Octrees of volumes that stay the same are kept.
    void setSeriesVolumes(const std::string& seriesUid, const std::vector<std::string>& varying);
    /// Replaces the series' assembly warnings (shown in the browser row and by `studies`).
    void setSeriesWarnings(const std::string& seriesUid, const std::vector<std::string>& warnings);
    std::vector<VolumeRow> volumesOfSeries(const std::string& seriesUid) const;
    /// As setSeriesOctree, for the N-th volume of a series.
    bool setVolumeOctree(const std::string& seriesUid, int number, const std::string& octreePath);
    std::size_t instanceCount() const;
    const std::string& path() const { return path_; }

private:
    void exec(const char* sql) const;
    /// Runs `body` in one write transaction, rolled back when it throws.
    void transaction(const std::function<void()>& body);
    /// Brings an older schema to kSchemaVersion; refuses a newer one.
    void migrate();
    std::string path_;
    sqlite3* db_ = nullptr;
    mutable bool lastFailureBusy_ = false;  ///< the last failed exec met a lock held by another connection
};

}  // namespace hvx::dicom
