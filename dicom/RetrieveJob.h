#pragma once
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "core/base/JobContext.h"
#include "dicom/PacsClient.h"
#include "dicom/PacsSettings.h"

namespace hvx::dicom {

class StudyDatabase;

/// Where one series of a retrieve stands.
struct SeriesRetrieveStatus {
    std::string seriesUid;
    std::string description;
    RetrieveProgress progress;
    bool retrieved = false;
    std::string octreePath;  ///< set once its octree is built
    std::string error;       ///< a failed series says why; the others go on
    int alreadyHere = 0;     ///< instances that were here (indexed, on disk) and were not fetched again
    int countOnPacs = 0;     ///< the series' instance count as the PACS gave it (0: not given)
};

/// Retrieves a study (or one series) from a PACS, several series at once over their own
/// associations (LocalNode::parallelAssociations; a PACS that rejects the extra associations is
/// waited for), by C-GET, by C-MOVE to Holovox's own storage SCP (started for the duration) or
/// by WADO-RS from a DICOMweb node, indexes every received instance into the study database,
/// and builds each finished series' octree on one builder thread while the transfers go on. Progress per series comes from the sub-operation counts. At
/// the end of each series the instances that arrived are counted against the PACS's own count
/// (the series-level count when nothing is here yet, else an image-level C-FIND): a partial series is reported as such, indexed but not built, and a
/// C-MOVE of which nothing arrived names the PACS's entry for our AE title as the likely cause.
/// Retrieving a series again (after a partial retrieve) fetches only the instances that are not
/// here already, by an image-level C-GET/C-MOVE of their SOP Instance UIDs, and builds from all.
///
/// Threading: run() blocks the calling (job) thread; onUpdate runs on it or on the build thread.
class RetrieveJob {
public:
    RetrieveJob(PacsSettings settings, PacsNode node, StudyDatabase& db, std::string octreeDir);
    /// Throws core::Error when nothing could be retrieved; per-series failures are reported in
    /// the returned statuses. Honours job cancellation between series.
    std::vector<SeriesRetrieveStatus> run(const std::string& studyUid, const std::string& seriesUid, bool buildOctrees,
                                          core::JobContext& job,
                                          const std::function<void(const SeriesRetrieveStatus&)>& onUpdate);

private:
    /// Retrieves one series (only what is not here already) and checks it is complete. Returns
    /// false with the reason in s.error when it failed; throws core::Cancelled.
    bool fetch(PacsClient& client, const std::string& studyUid, SeriesRetrieveStatus& s, std::mutex& mutex,
               std::map<std::string, std::vector<DicomInstance>>& received,
               const std::function<void(const DicomInstance&)>& onStored,
               const std::function<void(const RetrieveProgress&)>& progress);
    /// Throws core::Error when fewer instances of the series arrived than it has (counted by an
    /// image-level C-FIND, else by the sub-operations), naming the likely cause of a C-MOVE of
    /// which nothing arrived.
    void checkComplete(const SeriesRetrieveStatus& s, std::size_t expected, std::size_t arrived) const;
    /// The SOP Instance UIDs of a series on the PACS (image-level C-FIND); empty when the PACS
    /// cannot list them.
    std::vector<std::string> instancesOnPacs(PacsClient& client, const std::string& studyUid,
                                             const std::string& seriesUid) const;

    PacsSettings settings_;
    PacsNode node_;
    StudyDatabase& db_;
    std::string octreeDir_;
};

}  // namespace hvx::dicom
