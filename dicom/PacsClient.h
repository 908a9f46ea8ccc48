#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/base/Error.h"
#include "core/base/JobContext.h"
#include "dicom/DicomInstance.h"
#include "dicom/PacsNode.h"
#include "dicom/PacsQuery.h"

namespace hvx::dicom {

/// The node rejected the association (it may limit how many it serves at once): the caller
/// may wait and try again.
class AssociationRejected : public core::Error {
public:
    using core::Error::Error;
};

/// A DICOM client for one remote node — a DICOMweb node is served by DicomWebClient behind the
/// same calls (C-MOVE excepted): C-ECHO, Study Root C-FIND at study, series and image
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

    /// Files per association of a C-STORE of many files.
    static constexpr std::size_t kFilesPerAssociation = 200;

    /// Sends files to the node (C-STORE, or STOW-RS for a DICOMweb node); returns how many it
    /// accepted. Many files go over several associations at once (one per
    /// kFilesPerAssociation files, at most LocalNode::parallelAssociations); onProgress gets
    /// the count sent so far. Throws core::Error when the node refuses or the connection fails.
    std::size_t store(const std::vector<std::string>& files, const std::function<void(std::size_t)>& onProgress);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hvx::dicom
