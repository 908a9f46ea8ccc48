#include "dicom/SeriesOctree.h"

#include "core/base/AtomicFileWriter.h"
#include "dicom/SegmentationSource.h"
#include "dicom/StructureSetSource.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>

#include "core/base/Error.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/SubsampledVoxelSource.h"
#include "dicom/DicomScanner.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/SeriesAssembler.h"
#include "dicom/StudyDatabase.h"
#include "dicom/UidPath.h"

namespace hvx::dicom {

std::string SeriesOctree::folderFor(const std::string& dbPath) {
    return (std::filesystem::path(dbPath).parent_path() / "octrees").string();
}

namespace {
// The series' largest stack, assembled from its files in the database.
SeriesVolume assembleSeries(StudyDatabase& db, const std::string& seriesUid, core::JobContext& job,
                            std::vector<std::string>* warnings, int volume) {
    const auto files = db.filesOfSeries(seriesUid);
    if (files.empty()) throw core::Error("series " + seriesUid + " is not in the database (import it first)");
    core::JobContext scanJob;  // header scanning is quick next to building; progress comes from the build
    const auto scan = DicomScanner::scan(files, scanJob);
    job.throwIfCancelled();
    std::vector<std::string> notes;
    auto volumes = SeriesAssembler::assemble(scan.instances, notes);
    volumes.erase(std::remove_if(volumes.begin(), volumes.end(),
                                 [&](const SeriesVolume& v) { return v.seriesUid != seriesUid; }),
                  volumes.end());
    if (volumes.empty()) throw core::Error("series " + seriesUid + " has no image volume to build");
    std::size_t pick = 0;
    if (volume > 0) {
        if (std::size_t(volume) > volumes.size())
            throw core::Error("series " + seriesUid + " has " + std::to_string(volumes.size()) + " volume(s), not " +
                              std::to_string(volume));
        pick = std::size_t(volume - 1);
    } else {
        for (std::size_t i = 1; i < volumes.size(); ++i)
            if (volumes[i].slices.size() > volumes[pick].slices.size()) pick = i;
    }
    if (warnings) {
        warnings->insert(warnings->end(), notes.begin(), notes.end());
        warnings->insert(warnings->end(), volumes[pick].warnings.begin(), volumes[pick].warnings.end());
    }
    return volumes[pick];
}

std::string defaultPath(StudyDatabase& db, const std::string& seriesUid, const std::string& suffix) {
    std::filesystem::create_directories(SeriesOctree::folderFor(db.path()));
    return (std::filesystem::path(SeriesOctree::folderFor(db.path())) / (UidPath::component(seriesUid) + suffix)).string();
}
/// A label map's names and colours, kept beside its octree.
void writeTable(const core::LabelTable& table, const std::string& octreePath) {
    const std::string text = table.toSlicerTable();
    core::AtomicFileWriter w(core::LabelTable::sidecarPath(octreePath));
    w.append(text.data(), text.size());
    w.commit();
}
/// A SEG or RTSTRUCT series' first object built as a label map at `outPath`, its names and
/// colours beside it; its warnings, and that only the first of several `what` is shown, said.
void buildLabelMap(core::VoxelSource& source, const core::LabelTable& table, const std::vector<std::string>& files,
                   const std::string& what, std::vector<std::string>* warnings, const std::string& outPath,
                   core::JobContext& job) {
    if (warnings) {
        for (const auto& w : source.warnings()) warnings->push_back(w);
        if (files.size() > 1)
            warnings->push_back("the series holds " + std::to_string(files.size()) + " " + what +
                                ": the first is shown (" + files.front() + ")");
    }
    core::BuildOptions o;
    o.labels = true;
    core::OctreeBuilder(o).build(source, outPath, job);
    writeTable(table, outPath);
}
}  // namespace

std::string SeriesOctree::build(StudyDatabase& db, const std::string& seriesUid, core::JobContext& job,
                                std::vector<std::string>* warnings, std::string outPath, int volume) {
    // A segmentation series is a label map, with its segments' names and colours beside it.
    const auto files = db.filesOfSeries(seriesUid);
    if (!files.empty() && SegmentationSource::isSegmentation(files.front())) {
        SegmentationSource seg(files.front());
        if (outPath.empty()) outPath = defaultPath(db, seriesUid, ".hvo");
        buildLabelMap(seg, seg.table(), files, "segmentation objects", warnings, outPath, job);
        record(db, seriesUid, outPath);
        return outPath;
    }
    DicomSeriesSource source(assembleSeries(db, seriesUid, job, warnings, volume));
    const std::string suffix = volume > 0 ? "-v" + std::to_string(volume) : std::string();
    if (outPath.empty()) outPath = defaultPath(db, seriesUid, suffix + ".hvo");
    core::OctreeBuilder(core::BuildOptions{}).build(source, outPath, job);
    record(db, seriesUid, outPath, volume);
    return outPath;
}

void SeriesOctree::record(StudyDatabase& db, const std::string& seriesUid, const std::string& octreePath, int volume) {
    if (volume > 0 ? db.setVolumeOctree(seriesUid, volume, octreePath) : db.setSeriesOctree(seriesUid, octreePath)) return;
    std::error_code ec;
    std::filesystem::remove(octreePath, ec);
    std::filesystem::remove(core::LabelTable::sidecarPath(octreePath), ec);
    throw core::Error("series " + seriesUid + (volume > 0 ? " (volume " + std::to_string(volume) + ")" : std::string()) +
                      " is no longer in the study database (its study was removed while its octree was built): the "
                      "octree is deleted");
}

bool SeriesOctree::isStructureSet(StudyDatabase& db, const std::string& seriesUid) {
    const auto files = db.filesOfSeries(seriesUid);
    return !files.empty() && StructureSetSource::isStructureSet(files.front());
}

std::string SeriesOctree::buildStructureSet(StudyDatabase& db, const std::string& seriesUid,
                                            const core::VolumeGeometry& grid, core::JobContext& job,
                                            std::vector<std::string>* warnings, std::string outPath) {
    const auto files = db.filesOfSeries(seriesUid);
    if (files.empty() || !StructureSetSource::isStructureSet(files.front()))
        throw core::Error("series " + seriesUid + " is not an RT Structure Set");
    StructureSetSource rt(files.front(), grid);
    if (outPath.empty()) outPath = defaultPath(db, seriesUid, ".rt.hvo");
    buildLabelMap(rt, rt.table(), files, "structure sets", warnings, outPath, job);
    return outPath;
}

std::string SeriesOctree::buildPreview(StudyDatabase& db, const std::string& seriesUid, core::JobContext& job,
                                       std::uint32_t factor, int volume) {
    core::SubsampledVoxelSource source(
        std::make_unique<DicomSeriesSource>(assembleSeries(db, seriesUid, job, nullptr, volume)), factor);
    const std::string suffix = volume > 0 ? "-v" + std::to_string(volume) : std::string();
    const std::string out = defaultPath(db, seriesUid, suffix + ".preview.hvo");
    core::OctreeBuilder(core::BuildOptions{}).build(source, out, job);
    return out;
}

std::vector<SeriesVolume> SeriesOctree::recordVolumes(StudyDatabase& db, const std::vector<SeriesVolume>& scanned,
                                                      const std::vector<DicomInstance>& batch, std::mutex* dbMutex) {
    // A series whose images came in over several imports (two folders, two retrieves) is
    // assembled again from all its files that can be read: its gaps and volumes are the whole
    // series', not the last import's (a filled gap had kept its "missing slices" warning, a new
    // one had none). Counted against the batch, not the volumes, which leave some images out.
    // The database is read and written under `dbMutex`; the files are read without it, so that
    // a retrieve's receiver is never held up while a grown series is read again.
    auto locked = [dbMutex]() { return dbMutex ? std::unique_lock<std::mutex>(*dbMutex) : std::unique_lock<std::mutex>(); };
    std::map<std::string, std::set<std::string>> inBatch;  // series -> SOP Instance UIDs
    for (const auto& in : batch) inBatch[in.seriesInstanceUid].insert(in.sopInstanceUid);
    std::set<std::string> grown;  // series to assemble whole from all their files
    std::vector<SeriesVolume> volumes;
    {
        auto lock = locked();
        for (const auto& v : scanned) {
            if (grown.count(v.seriesUid)) continue;
            SeriesRow row;
            if (db.findSeries(v.seriesUid, row) && std::size_t(row.instanceCount) > inBatch[v.seriesUid].size())
                grown.insert(v.seriesUid);
            else
                volumes.push_back(v);
        }
    }
    for (const auto& uid : grown) {
        // Read again until the count holds: another import of the same series while its files
        // were read would otherwise be recorded over by the older, smaller reading.
        for (int attempt = 0;; ++attempt) {
            std::vector<std::string> files;
            {
                auto lock = locked();
                files = db.filesOfSeries(uid);
            }
            std::vector<std::string> readable;
            std::error_code ec;
            for (const auto& f : files)
                if (std::filesystem::exists(f, ec)) readable.push_back(f);  // an unmounted folder's are left out
            core::JobContext scanJob;
            const auto scan = DicomScanner::scan(readable, scanJob);
            std::vector<std::string> notes;
            std::vector<SeriesVolume> parts;
            for (auto& part : SeriesAssembler::assemble(scan.instances, notes))
                if (part.seriesUid == uid) parts.push_back(std::move(part));
            SeriesRow row;
            auto lock = locked();
            if (attempt < 3 && db.findSeries(uid, row) && row.instanceCount != std::int64_t(files.size())) continue;
            for (auto& part : parts) volumes.push_back(std::move(part));
            break;
        }
    }
    std::map<std::string, std::vector<std::string>> bySeries, warnings;
    for (const auto& v : volumes) {
        bySeries[v.seriesUid].push_back(v.varying.empty() ? v.label : v.varying);
        auto& w = warnings[v.seriesUid];
        for (const auto& text : v.warnings)
            if (std::find(w.begin(), w.end(), text) == w.end()) w.push_back(text);
    }
    auto lock = locked();
    for (const auto& [uid, varying] : bySeries) {
        db.setSeriesVolumes(uid, varying.size() > 1 ? varying : std::vector<std::string>{});
        db.setSeriesWarnings(uid, warnings[uid]);
    }
    return volumes;
}

SeriesVolume SeriesOctree::assemble(StudyDatabase& db, const std::string& seriesUid, core::JobContext& job,
                                   std::vector<std::string>* warnings, int volume) {
    return assembleSeries(db, seriesUid, job, warnings, volume);
}

}  // namespace hvx::dicom
