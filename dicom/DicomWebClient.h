#pragma once
#include <functional>
#include <string>
#include <vector>

#include "core/base/JobContext.h"
#include "dicom/DicomInstance.h"
#include "dicom/PacsNode.h"
#include "dicom/PacsQuery.h"

namespace hvx::dicom {

/// A DICOMweb client for one node (PS3.18): QIDO-RS search at study, series and instance level
/// with C-FIND's matching keys, answers delivered page by page as they arrive; WADO-RS retrieve
/// of a study, a series or chosen instances as multipart/related application/dicom, streamed
/// part by part into the IncomingStore (never held whole, the stored transfer syntax kept);
/// STOW-RS upload of files in batches. Errors are sentences (see HttpRequest): unreachable,
/// TLS, credentials, not found, too large, storage full, an answer that is not a DICOM JSON
/// model or not a well-formed multipart body.
///
/// Threading: one operation at a time per object; callbacks run on the calling thread.
class DicomWebClient {
public:
    /// Results per QIDO-RS request (limit/offset paging).
    static constexpr int kPageSize = 100;
    /// Files per STOW-RS request.
    static constexpr std::size_t kStowBatch = 100;

    DicomWebClient(LocalNode local, PacsNode remote);
    /// Transfers stop when `job` is cancelled (core::Cancelled); `job` must outlive this.
    void cancelWith(const core::JobContext& job) { job_ = &job; }

    /// Checks that the service answers a QIDO-RS search (the DICOMweb counterpart of C-ECHO).
    void echo();
    std::size_t find(QueryLevel level, const QueryKeys& keys, const std::function<bool(const QueryResult&)>& onResult);
    /// As PacsClient::get: `progress.received` counts the instances stored.
    RetrieveProgress get(const std::string& studyUid, const std::string& seriesUid, const std::string& storageDir,
                         const std::function<void(const DicomInstance&)>& onStored,
                         const std::function<void(const RetrieveProgress&)>& onProgress,
                         const std::vector<std::string>& sopUids = {});
    /// Uploads files, kStowBatch to a request and LocalNode::parallelAssociations requests at
    /// once (onProgress from those threads, one call at a time); returns how many the server
    /// stored. Throws core::Error when a file is not DICOM, or the server refuses a request.
    std::size_t store(const std::vector<std::string>& files, const std::function<void(std::size_t)>& onProgress);

    /// The QIDO-RS URL of one page of a search (exposed for tests).
    std::string queryUrl(QueryLevel level, const QueryKeys& keys, int offset) const;

private:
    std::string what() const;
    void retrieve(const std::string& url, class IncomingStore& store, RetrieveProgress& progress,
                  const std::function<void(const DicomInstance&)>& onStored,
                  const std::function<void(const RetrieveProgress&)>& onProgress);
    std::size_t storeBatch(const std::vector<std::string>& files);

    LocalNode local_;
    PacsNode remote_;
    const core::JobContext* job_ = nullptr;
};

}  // namespace hvx::dicom
