#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/base/JobContext.h"
#include "dicom/DicomInstance.h"
#include "dicom/PacsNode.h"

namespace hvx::dicom {

/// Query/retrieve level of a Study Root C-FIND.
enum class QueryLevel { Study, Series, Image };

/// Matching keys of a query. Empty keys match everything. patientName takes DICOM wildcards
/// (* and ?); studyDate is YYYYMMDD or a range "YYYYMMDD-YYYYMMDD" (either end may be open).
struct QueryKeys {
    std::string patientName, patientId, studyDate, modality, accessionNumber, studyDescription;
    std::string studyUid, seriesUid;  ///< restrict SERIES and IMAGE queries
};

/// One C-FIND answer.
struct QueryResult {
    QueryLevel level = QueryLevel::Study;
    std::string patientName, patientId, patientBirthDate;
    std::string studyUid, studyDate, studyTime, studyDescription, accessionNumber, modalitiesInStudy;
    std::string seriesUid, seriesDescription, modality;
    int seriesNumber = 0, instanceNumber = 0, numberOfInstances = 0;
    std::string sopInstanceUid;
};

/// Sub-operation counts of a running C-GET or C-MOVE, from the PACS's pending responses.
struct RetrieveProgress {
    int remaining = 0, completed = 0, failed = 0, warning = 0;
    int received = 0;  ///< instances this client stored itself (C-GET)
};

/// A DICOM client for one remote node: C-ECHO, Study Root C-FIND at study, series and image
/// level (results stream to a callback; returning false sends C-CANCEL), C-GET with storage
/// role negotiation, and C-MOVE to a destination AE. Every failure is a core::Error in plain
/// words that says what to check (host and port, AE titles, move destination).
///
/// Threading: one operation at a time per object; callbacks run on the calling thread.
class PacsClient {
public:
    PacsClient(LocalNode local, PacsNode remote);
    ~PacsClient();
    PacsClient(const PacsClient&) = delete;
    PacsClient& operator=(const PacsClient&) = delete;

    /// Retrieves stop when `job` is cancelled: a C-CANCEL is sent at the next response, and
    /// the association is aborted at the next instance that arrives. `job` must outlive this.
    void cancelWith(const core::JobContext& job);

    void echo();
    /// Returns the number of results delivered.
    std::size_t find(QueryLevel level, const QueryKeys& keys, const std::function<bool(const QueryResult&)>& onResult);
    /// Retrieves a study (or one series of it, or with `sopUids` only those instances of the
    /// series) by C-GET into `storageDir` (IncomingStore layout). onStored is called for each
    /// instance written; onProgress for each response.
    RetrieveProgress get(const std::string& studyUid, const std::string& seriesUid, const std::string& storageDir,
                         const std::function<void(const DicomInstance&)>& onStored,
                         const std::function<void(const RetrieveProgress&)>& onProgress,
                         const std::vector<std::string>& sopUids = {});
    /// Asks the node to C-MOVE a study (or series, or those instances of it) to `destinationAe`.
    RetrieveProgress move(const std::string& studyUid, const std::string& seriesUid, const std::string& destinationAe,
                          const std::function<void(const RetrieveProgress&)>& onProgress,
                          const std::vector<std::string>& sopUids = {});

    /// Sends files to the node by C-STORE (one association); returns how many it accepted.
    /// Throws core::Error when the node refuses or the connection fails.
    std::size_t store(const std::vector<std::string>& files, const std::function<void(std::size_t)>& onProgress);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hvx::dicom
