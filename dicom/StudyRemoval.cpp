#include "dicom/StudyRemoval.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/IncomingStore.h"
#include "dicom/StorageOwners.h"
#include "dicom/StudyDatabase.h"
#include "dicom/UidPath.h"

namespace fs = std::filesystem;

namespace hvx::dicom {

namespace {
/// A path with its folder resolved (links, "..", relative) and its own name kept as it is, so
/// that a link is compared as the link, not as what it points to.
fs::path resolvedFolder(const fs::path& p) {
    std::error_code ec;
    const fs::path folder = fs::weakly_canonical(fs::absolute(p, ec).parent_path(), ec);
    return ec ? fs::path() : folder / p.filename();
}

/// Whether `file` is where IncomingStore puts an instance it received (IncomingStore::placeOf
/// under `root`, the storage folder resolved), and a plain file, not a link. Mere containment
/// would not do: a storage folder of "/" or the home folder holds the user's own files too.
bool receivedHere(const fs::path& root, const std::string& studyUid, const StudyDatabase::RemovedStudy::File& f) {
    if (root.empty()) return false;
    std::error_code ec;
    return resolvedFolder(f.path) == fs::path(IncomingStore::placeOf(root.string(), studyUid, f.seriesUid, f.sopUid)) &&
           fs::is_regular_file(fs::symlink_status(f.path, ec)) && !ec;
}

/// Whether `name` is one of the octree files SeriesOctree, retrieves and `import --build` make
/// for a series whose UID's path component is `stem`: "<stem>.hvo", ".preview.hvo", ".rt.hvo",
/// "<stem>-vN" with either of the first two, and "<stem>-stackN.hvo" (a UID's dots make a
/// plain prefix test match other series).
bool octreeOf(const std::string& name, const std::string& stem) {
    if (name.compare(0, stem.size(), stem) != 0) return false;
    std::string rest = name.substr(stem.size());
    for (const std::string numbered : {"-v", "-stack"}) {
        if (rest.rfind(numbered, 0) != 0) continue;
        std::size_t end = numbered.size();
        while (end < rest.size() && std::isdigit(static_cast<unsigned char>(rest[end]))) ++end;
        if (end == numbered.size()) return false;
        rest = rest.substr(end);
        return rest == ".hvo" || (numbered == "-v" && rest == ".preview.hvo");
    }
    return rest == ".hvo" || rest == ".preview.hvo" || rest == ".rt.hvo";
}

/// Indexes again the received files that could not be deleted (their rows are gone): what
/// stays in the storage folder stays known. Returns how many; a file whose header cannot be
/// read any more is only named (StudyRemoval::Result::failed).
std::size_t indexAgain(StudyDatabase& db, const std::vector<std::string>& paths) {
    std::vector<DicomInstance> again;
    for (const auto& path : paths) {
        DicomInstance in;
        try {
            if (DicomHeaderReader::read(path, in) == DicomHeaderReader::Kind::Dicom) again.push_back(std::move(in));
        } catch (const core::Error&) {
        }
    }
    if (again.empty()) return 0;
    const auto stats = db.addInstances(again);
    return stats.added + stats.unchanged + stats.moved;
}

void removeFile(const fs::path& file, std::size_t& count, std::vector<std::string>& failed) {
    std::error_code ec;
    if (fs::remove(file, ec)) ++count;
    else if (ec) failed.push_back(file.string() + ": " + ec.message());
}
}  // namespace

StudyRemoval::Result StudyRemoval::remove(StudyDatabase& db, const std::string& studyUid, const std::string& storageDir,
                                          const std::string& octreeDir) {
    // The rows first: the index never points at a deleted file; a file that cannot be deleted
    // is said, and stays.
    const auto removed = db.removeStudy(studyUid);
    Result r;
    r.patient = removed.patient;
    r.forgotten = removed.files.size();
    std::error_code ec;
    const fs::path root = storageDir.empty() ? fs::path() : fs::weakly_canonical(fs::absolute(storageDir, ec), ec);
    // Received files that another database sharing the folder indexes stay; all of them when
    // one of those cannot be read.
    std::vector<std::string> candidates;
    for (const auto& f : removed.files)
        if (!ec && receivedHere(root, studyUid, f)) candidates.push_back(f.path);
    std::set<std::string> shared;
    if (!candidates.empty())
        for (const auto& other : StorageOwners::othersThan(storageDir, db.path())) {
            try {
                const auto indexed = StudyDatabase::indexedPaths(other, candidates);
                if (!indexed.empty()) r.sharers.push_back(other);
                shared.insert(indexed.begin(), indexed.end());
            } catch (const core::Error& e) {
                r.sharers.push_back(e.what());
                shared.insert(candidates.begin(), candidates.end());
            }
        }
    std::set<fs::path> folders;  // the series folders emptied, then their study folder
    std::vector<std::string> undeleted;
    for (const auto& f : removed.files) {
        if (ec || !receivedHere(root, studyUid, f)) {
            ++r.kept;
            continue;
        }
        if (shared.count(f.path)) {
            ++r.shared;
            continue;
        }
        const std::size_t failures = r.failed.size();
        removeFile(f.path, r.deleted, r.failed);
        if (r.failed.size() == failures) folders.insert(resolvedFolder(f.path).parent_path());
        else undeleted.push_back(f.path);
    }
    r.reindexed = indexAgain(db, undeleted);
    std::set<fs::path> studies;
    for (const auto& series : folders) {
        if (fs::is_empty(series, ec) && !ec) fs::remove(series, ec);
        studies.insert(series.parent_path());
    }
    for (const auto& study : studies)
        if (fs::is_empty(study, ec) && !ec) fs::remove(study, ec);
    // The octrees recorded for the study, and those made for its series without a record
    // (previews, structure sets drawn onto a grid), inside the octree folder; never one that
    // the database still records for another series.
    std::set<fs::path> recordedElsewhere;
    for (const auto& o : db.recordedOctrees()) recordedElsewhere.insert(resolvedFolder(o));
    std::set<fs::path> octrees;
    for (const auto& o : removed.octrees) octrees.insert(resolvedFolder(o));
    if (!octreeDir.empty() && fs::is_directory(octreeDir, ec))
        for (const auto& entry : fs::directory_iterator(octreeDir, ec))
            for (const auto& uid : removed.series)
                if (octreeOf(entry.path().filename().string(), UidPath::component(uid)))
                    octrees.insert(resolvedFolder(entry.path()));
    const fs::path folder = octreeDir.empty() ? fs::path() : fs::weakly_canonical(fs::absolute(octreeDir, ec), ec);
    for (const auto& o : octrees)
        if (!folder.empty() && o.parent_path() == folder && !recordedElsewhere.count(o) &&
            fs::is_regular_file(fs::symlink_status(o, ec)))
            removeFile(o, r.octrees, r.failed);
    return r;
}

}  // namespace hvx::dicom
