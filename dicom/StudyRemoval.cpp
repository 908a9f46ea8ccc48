#include "dicom/StudyRemoval.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "dicom/StudyDatabase.h"
#include "dicom/UidPath.h"

namespace fs = std::filesystem;

namespace hvx::dicom {

namespace {
/// Whether `file` lies inside `folder` (both resolved: a link or ".." cannot lead out of it).
bool inside(const fs::path& folder, const fs::path& file) {
    if (folder.empty()) return false;
    std::error_code ec;
    const fs::path f = fs::weakly_canonical(folder, ec);
    if (ec) return false;
    const fs::path p = fs::weakly_canonical(file, ec);
    if (ec) return false;
    const auto [end, at] = std::mismatch(f.begin(), f.end(), p.begin(), p.end());
    return end == f.end() && at != p.end();
}

/// Whether `name` is one of the octree files SeriesOctree and retrieves make for a series whose
/// UID's path component is `stem`: "<stem>.hvo", ".preview.hvo", ".rt.hvo", and "<stem>-vN"
/// with either of the first two (a UID's dots make a plain prefix test match other series).
bool octreeOf(const std::string& name, const std::string& stem) {
    if (name.compare(0, stem.size(), stem) != 0) return false;
    std::string rest = name.substr(stem.size());
    if (rest.rfind("-v", 0) == 0) {
        std::size_t digits = 2;
        while (digits < rest.size() && std::isdigit(static_cast<unsigned char>(rest[digits]))) ++digits;
        if (digits == 2) return false;
        rest = rest.substr(digits);
        return rest == ".hvo" || rest == ".preview.hvo";
    }
    return rest == ".hvo" || rest == ".preview.hvo" || rest == ".rt.hvo";
}

void removeFile(const fs::path& file, std::size_t& count, std::vector<std::string>& failed) {
    std::error_code ec;
    if (fs::remove(file, ec)) ++count;
    else if (ec) failed.push_back(file.string() + ": " + ec.message());
}

/// Removes the folders between `file` and `top` that are left empty.
void removeEmptyFolders(const fs::path& top, fs::path file) {
    std::error_code ec;
    const fs::path stop = fs::weakly_canonical(top, ec);
    for (fs::path dir = fs::weakly_canonical(file, ec).parent_path(); !ec && dir != stop && inside(stop, dir);
         dir = dir.parent_path())
        if (!fs::is_empty(dir, ec) || ec || !fs::remove(dir, ec)) break;
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
    for (const auto& f : removed.files) {
        if (!inside(storageDir, f)) {
            ++r.kept;
            continue;
        }
        std::size_t before = r.failed.size();
        std::size_t deleted = 0;
        removeFile(f, deleted, r.failed);
        r.deleted += deleted;
        if (r.failed.size() == before) removeEmptyFolders(storageDir, f);
    }
    // The octrees recorded, and those made for the series without a record (previews, structure
    // sets drawn onto a grid).
    std::vector<fs::path> octrees(removed.octrees.begin(), removed.octrees.end());
    std::error_code ec;
    if (!octreeDir.empty() && fs::is_directory(octreeDir, ec))
        for (const auto& entry : fs::directory_iterator(octreeDir, ec)) {
            const std::string name = entry.path().filename().string();
            for (const auto& uid : removed.series)
                if (octreeOf(name, UidPath::component(uid))) octrees.push_back(entry.path());
        }
    std::sort(octrees.begin(), octrees.end());
    octrees.erase(std::unique(octrees.begin(), octrees.end()), octrees.end());
    for (const auto& o : octrees)
        if (inside(octreeDir, o) && fs::exists(o, ec)) removeFile(o, r.octrees, r.failed);
    return r;
}

}  // namespace hvx::dicom
