#pragma once
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "core/base/JobContext.h"
#include "dicom/SeriesVolume.h"

namespace hvx::dicom {

class StudyDatabase;

/// Builds the octree of one imported series from its files in the study database: scan the
/// headers, assemble the volume (the largest stack when a series holds several), stream it into
/// an .hvo and record it in the database. Shared by the GUI's open-series job and the CLI.
///
/// Threading: call from a job thread with its own StudyDatabase connection.
class SeriesOctree {
public:
    /// Where octrees of the database at `dbPath` are kept: `<its folder>/octrees`.
    static std::string folderFor(const std::string& dbPath);
    /// Builds `seriesUid` into `outPath` (default: folderFor(db)/<uid>.hvo) and returns the
    /// path; warnings of assembly (gaps, tilt...) are appended to `warnings`. Throws core::Error
    /// for an unknown series or one with no image volume; core::Cancelled when cancelled.
    /// `volume` 0 is the series' largest volume; N >= 1 is the N-th volume of a 4D series (as
    /// StudyDatabase::volumesOfSeries numbers them), kept at `<uid>-vN.hvo`.
    static std::string build(StudyDatabase& db, const std::string& seriesUid, core::JobContext& job,
                             std::vector<std::string>* warnings = nullptr, std::string outPath = {}, int volume = 0);
    /// An RT Structure Set series drawn as a label map onto `grid` (the geometry of the image
    /// it is shown over), with its ROIs' names and colours beside it; at `outPath` (default:
    /// folderFor(db)/<uid>.rt.hvo, made again for each grid and not recorded, as it depends on
    /// the grid). Throws core::Error when the series is not a structure set or does not fit
    /// the grid (another frame of reference, contours between slices).
    static std::string buildStructureSet(StudyDatabase& db, const std::string& seriesUid,
                                         const core::VolumeGeometry& grid, core::JobContext& job,
                                         std::vector<std::string>* warnings = nullptr, std::string outPath = {});
    /// Records `octreePath` as the series' octree (volume 0) or its N-th volume's in `db`. When
    /// the series is no longer there (its study was removed while the octree was built), deletes
    /// the octree (and a label map's names beside it), recorded nowhere, and throws core::Error
    /// saying so.
    static void record(StudyDatabase& db, const std::string& seriesUid, const std::string& octreePath, int volume = 0);
    /// Whether the series' objects are RT Structure Sets (contours, drawn onto an image's grid).
    static bool isStructureSet(StudyDatabase& db, const std::string& seriesUid);
    /// A quick preview octree of every `factor`-th voxel (reading one slice in `factor`), at
    /// `<folder>/<uid>.preview.hvo`, for showing a series while its full octree builds. Not
    /// recorded in the database.
    static std::string buildPreview(StudyDatabase& db, const std::string& seriesUid, core::JobContext& job,
                                    std::uint32_t factor = 4, int volume = 0);
    /// The series' volume (0: its largest; N: the N-th of a 4D series) assembled from its files
    /// in the database, with the warnings of assembly appended to `warnings`.
    static SeriesVolume assemble(StudyDatabase& db, const std::string& seriesUid, core::JobContext& job,
                                 std::vector<std::string>* warnings = nullptr, int volume = 0);
    /// Records in the database the volumes of every series in `volumes` that splits into several
    /// (what varies between them), and each series' assembly warnings, as import and retrieve
    /// find them; a series the database holds more images of than `batch` (the instances those
    /// volumes were assembled from) is assembled again from all its files that can be read
    /// first. Returns the volumes recorded: what import lists and builds. With `dbMutex`, the
    /// database is used only while it is held, and the files are read without it.
    static std::vector<SeriesVolume> recordVolumes(StudyDatabase& db, const std::vector<SeriesVolume>& volumes,
                                                   const std::vector<DicomInstance>& batch,
                                                   std::mutex* dbMutex = nullptr);
};

}  // namespace hvx::dicom
