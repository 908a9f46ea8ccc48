#include "dicom/DicomWebClient.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <atomic>
#include <memory>
#include <mutex>
#include <thread>
#include <random>
#include <set>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomJson.h"
#include "dicom/DicomWebUrl.h"
#include "dicom/HttpRequest.h"
#include "dicom/IncomingFiler.h"
#include "dicom/IncomingStore.h"
#include "dicom/MultipartReader.h"

namespace hvx::dicom {

namespace {
const char* kAcceptDicom = "Accept: multipart/related; type=\"application/dicom\"; transfer-syntax=*";

/// Writes each part of a WADO-RS answer to a temporary file of the store and, when the part is
/// complete, hands it to an IncomingFiler, which files it while the next parts arrive; a part
/// left incomplete is removed. Filed instances are reported on the receiving thread.
class WadoSink : public MultipartReader::Sink {
public:
    WadoSink(IncomingStore& store, std::function<void(const DicomInstance&)> onStored)
        : store_(store), filer_(store), onStored_(std::move(onStored)) {}
    ~WadoSink() override { discard(); }
    WadoSink(const WadoSink&) = delete;
    WadoSink& operator=(const WadoSink&) = delete;

    void beginPart(const std::map<std::string, std::string>& headers) override {
        if (const auto it = headers.find("content-type"); it != headers.end() &&
                                                          it->second.rfind("application/dicom", 0) != 0)
            throw core::Error("a part of the answer is '" + it->second + "', not a DICOM instance");
        path_ = store_.temporaryFile(fd_);
        buffered_ = 0;
    }
    void partData(const char* data, std::size_t size) override {
        if (buffered_ + size > buffer_.size()) flush();
        if (size >= buffer_.size()) return writeAll(data, size);
        std::memcpy(buffer_.data() + buffered_, data, size);
        buffered_ += size;
    }
    void endPart() override {
        flush();
        const bool ok = ::close(std::exchange(fd_, -1)) == 0;
        if (!ok) throw core::Error("cannot write " + path_ + " (disk full?)");
        filer_.submit(std::exchange(path_, std::string()), onStored_);  // the filer removes a file that is not DICOM
    }
    /// Waits for the instances being filed and reports them; throws the first one's error.
    void finish() { filer_.finish(onStored_); }
    /// After a failed transfer: the instances already filed are reported all the same.
    void finishAfterFailure() { filer_.finishAfterFailure(onStored_); }

private:
    void flush() {
        writeAll(buffer_.data(), buffered_);
        buffered_ = 0;
    }
    void writeAll(const char* data, std::size_t size) {
        while (size > 0) {
            const ssize_t n = ::write(fd_, data, size);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) throw core::Error("cannot write " + path_ + " (" + std::strerror(errno) + ")");
            data += n;
            size -= std::size_t(n);
        }
    }
    void discard() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
        if (!path_.empty()) std::remove(path_.c_str());
        path_.clear();
    }
    IncomingStore& store_;
    IncomingFiler filer_;
    std::function<void(const DicomInstance&)> onStored_;
    std::string path_;
    int fd_ = -1;
    std::vector<char> buffer_ = std::vector<char>(std::size_t(1) << 20);  // writes of 1 MiB, not of each chunk
    std::size_t buffered_ = 0;
};

std::string randomBoundary() {
    std::random_device rd;
    char buf[40];
    std::snprintf(buf, sizeof buf, "holovox-%08x%08x%08x", rd(), rd(), rd());
    return buf;
}

void param(std::string& url, const char* name, const std::string& value) {
    if (value.empty() || value == "*") return;
    url += (url.find('?') == std::string::npos ? '?' : '&');
    url += name;
    url += '=';
    url += DicomWebUrl::encode(value);
}
}  // namespace

DicomWebClient::DicomWebClient(LocalNode local, PacsNode remote) : local_(std::move(local)), remote_(std::move(remote)) {}

std::string DicomWebClient::what() const { return "DICOMweb node '" + remote_.name + "' (" + remote_.baseUrl + ")"; }

namespace {
HttpEndpoint endpointOf(const PacsNode& n, const LocalNode& l, const std::string& what) {
    HttpEndpoint e;
    e.what = what;
    e.bearerToken = n.bearerToken;
    e.username = n.username;
    e.password = n.password;
    e.tlsVerify = n.tlsVerify;
    e.timeoutSeconds = l.timeoutSeconds;
    return e;
}
}  // namespace

void DicomWebClient::echo() {
    HttpRequest r(endpointOf(remote_, local_, what()), DicomWebUrl::root(remote_.baseUrl) + "/studies?limit=1");
    r.header("Accept: application/dicom+json");
    const HttpAnswer a = r.send();
    if (a.status < 200 || a.status >= 300) throw core::Error(HttpRequest::describeStatus(what(), a.status, a.body));
    (void)DicomJson::queryResults(a.body, QueryLevel::Study, what());
}

std::string DicomWebClient::queryUrl(QueryLevel level, const QueryKeys& k, int offset) const {
    std::string url = DicomWebUrl::root(remote_.baseUrl);
    const std::string study = DicomWebUrl::encode(k.studyUid), series = DicomWebUrl::encode(k.seriesUid);
    bool studyInPath = false, seriesInPath = false;
    if (level == QueryLevel::Study) {
        url += "/studies";
    } else if (level == QueryLevel::Series) {
        studyInPath = !k.studyUid.empty();
        url += studyInPath ? "/studies/" + study + "/series" : "/series";
    } else {
        studyInPath = !k.studyUid.empty();
        seriesInPath = studyInPath && !k.seriesUid.empty();
        url += seriesInPath ? "/studies/" + study + "/series/" + series + "/instances"
                            : studyInPath ? "/studies/" + study + "/instances" : "/instances";
    }
    param(url, "PatientName", k.patientName);
    param(url, "PatientID", k.patientId);
    param(url, "StudyDate", k.studyDate);
    param(url, "AccessionNumber", k.accessionNumber);
    param(url, "StudyDescription", k.studyDescription);
    if (!studyInPath) param(url, "StudyInstanceUID", k.studyUid);
    if (level != QueryLevel::Study && !seriesInPath) param(url, "SeriesInstanceUID", k.seriesUid);
    param(url, level == QueryLevel::Study ? "ModalitiesInStudy" : "Modality", k.modality);
    // The attributes C-FIND asks for that are not among QIDO-RS's defaults.
    param(url, "includefield",
          level == QueryLevel::Study    ? "00100030,00081030,00080061,00201208"
          : level == QueryLevel::Series ? "0008103E,00200011,00201209,00100010,00100020"
                                        : "00200013,00200011,0008103E");
    param(url, "limit", std::to_string(kPageSize));
    if (offset > 0) param(url, "offset", std::to_string(offset));
    return url;
}

std::size_t DicomWebClient::find(QueryLevel level, const QueryKeys& keys,
                                 const std::function<bool(const QueryResult&)>& onResult) {
    std::set<std::string> seen;  // a server that ignores offset must not loop forever
    std::size_t delivered = 0;
    for (int offset = 0;; offset += kPageSize) {
        HttpRequest r(endpointOf(remote_, local_, what()), queryUrl(level, keys, offset));
        r.header("Accept: application/dicom+json");
        if (job_) r.cancelWith(job_);
        const HttpAnswer a = r.send();
        if (a.status == 204) break;  // no (more) matches
        if (a.status < 200 || a.status >= 300)
            throw core::Error(HttpRequest::describeStatus(what() + " (QIDO-RS search)", a.status, a.body));
        const auto results = DicomJson::queryResults(a.body, level, what());
        std::size_t fresh = 0;
        for (const auto& res : results) {
            const std::string id = res.studyUid + "/" + res.seriesUid + "/" + res.sopInstanceUid;
            if (!seen.insert(id).second) continue;
            ++fresh;
            ++delivered;
            if (onResult && !onResult(res)) return delivered;
        }
        // A short page ends the search, as does one larger than asked (the server ignores
        // paging) or one with nothing new (it ignores offset).
        if (results.size() != std::size_t(kPageSize) || fresh == 0) break;
    }
    return delivered;
}

void DicomWebClient::retrieve(const std::string& url, IncomingStore& store, RetrieveProgress& progress,
                              const std::function<void(const DicomInstance&)>& onStored,
                              const std::function<void(const RetrieveProgress&)>& onProgress) {
    WadoSink sink(store, [&](const DicomInstance& in) {
        ++progress.received;
        ++progress.completed;
        if (onStored) onStored(in);
        if (onProgress) onProgress(progress);
    });
    std::unique_ptr<MultipartReader> reader;
    HttpRequest r(endpointOf(remote_, local_, what()), url);
    r.header(kAcceptDicom);
    if (job_) r.cancelWith(job_);
    r.onBody([&](const std::string& type) { reader = std::make_unique<MultipartReader>(MultipartReader::boundaryOf(type), sink, local_.maxInstanceBytes); },
             [&](const char* data, std::size_t n) { reader->feed(data, n); });
    HttpAnswer a;
    try {
        a = r.send();
        if (a.status >= 200 && a.status < 300) {
            if (!reader) {  // no body at all: say what is wrong with its type, else that it is empty
                (void)MultipartReader::boundaryOf(a.contentType);
                throw core::Error("the answer is empty: no instance was sent");
            }
            reader->finish();
        }
        sink.finish();
    } catch (const core::Cancelled&) {
        sink.finishAfterFailure();
        throw;
    } catch (const core::Error& e) {
        sink.finishAfterFailure();
        throw core::Error(what() + " (WADO-RS retrieve): " + e.what() + " (" + std::to_string(progress.received) +
                          " instances were stored completely)");
    }
    if (a.status < 200 || a.status >= 300)
        throw core::Error(HttpRequest::describeStatus(what() + " (WADO-RS retrieve)", a.status, a.body));
}

RetrieveProgress DicomWebClient::get(const std::string& studyUid, const std::string& seriesUid,
                                     const std::string& storageDir,
                                     const std::function<void(const DicomInstance&)>& onStored,
                                     const std::function<void(const RetrieveProgress&)>& onProgress,
                                     const std::vector<std::string>& sopUids) {
    IncomingStore store(storageDir, local_.minFreeBytes);
    RetrieveProgress progress;
    std::string url = DicomWebUrl::root(remote_.baseUrl) + "/studies/" + DicomWebUrl::encode(studyUid);
    if (!seriesUid.empty()) url += "/series/" + DicomWebUrl::encode(seriesUid);
    if (sopUids.empty()) {
        retrieve(url, store, progress, onStored, onProgress);
        return progress;
    }
    if (seriesUid.empty()) throw core::Error(what() + ": instances are retrieved by series; no series was given");
    progress.remaining = int(sopUids.size());
    for (const auto& sop : sopUids) {
        retrieve(url + "/instances/" + DicomWebUrl::encode(sop), store, progress, onStored, onProgress);
        --progress.remaining;
    }
    return progress;
}

std::size_t DicomWebClient::store(const std::vector<std::string>& files, const std::function<void(std::size_t)>& onProgress) {
    for (const auto& f : files) {
        DicomInstance in;
        if (DicomHeaderReader::read(f, in) != DicomHeaderReader::Kind::Dicom) throw core::Error(f + ": not a DICOM file");
    }
    // Requests of kStowBatch files, `parallelAssociations` of them at once, each worker taking
    // the next batch; the first error stops the others after their request.
    const std::size_t batches = (files.size() + kStowBatch - 1) / kStowBatch;
    std::mutex mutex;
    std::size_t sent = 0;
    std::exception_ptr failure;
    std::atomic<std::size_t> next{0}, accepted{0};
    auto work = [&] {
        try {
            for (std::size_t b = next++; b < batches; b = next++) {
                if (job_) job_->throwIfCancelled();
                const std::size_t at = b * kStowBatch;
                const std::vector<std::string> batch(files.begin() + long(at),
                                                     files.begin() + long(std::min(files.size(), at + kStowBatch)));
                accepted += storeBatch(batch);
                std::lock_guard lock(mutex);
                sent += batch.size();
                if (onProgress) onProgress(sent);
            }
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!failure) failure = std::current_exception();
            next = batches;
        }
    };
    const int workers = int(std::min<std::size_t>(std::size_t(std::max(1, local_.parallelAssociations)), batches));
    std::vector<std::thread> threads;
    for (int i = 1; i < workers; ++i) threads.emplace_back(work);
    work();
    for (auto& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
    return accepted;
}

std::size_t DicomWebClient::storeBatch(const std::vector<std::string>& files) {
    // The body is streamed: boundary lines from memory, each file read from disk as curl asks.
    const std::string boundary = randomBoundary();
    struct Segment {
        std::string text;  // when path is empty
        std::string path;
        std::uint64_t size = 0;
    };
    std::vector<Segment> segments;
    std::uint64_t total = 0;
    for (const auto& f : files) {
        const std::uint64_t size = std::filesystem::file_size(f);
        segments.push_back({"--" + boundary + "\r\nContent-Type: application/dicom\r\nContent-Length: " +
                                std::to_string(size) + "\r\n\r\n", {}, 0});
        segments.push_back({{}, f, size});
        segments.push_back({"\r\n", {}, 0});
    }
    segments.push_back({"--" + boundary + "--\r\n", {}, 0});
    for (const auto& s : segments) total += s.path.empty() ? s.text.size() : s.size;

    std::size_t index = 0;
    std::uint64_t offset = 0;
    std::ifstream file;
    auto source = [&](char* buffer, std::size_t room) -> std::size_t {
        std::size_t written = 0;
        while (written < room && index < segments.size()) {
            const Segment& s = segments[index];
            if (s.path.empty()) {
                const std::size_t n = std::min<std::size_t>(room - written, s.text.size() - offset);
                std::copy_n(s.text.data() + offset, n, buffer + written);
                written += n;
                offset += n;
                if (offset == s.text.size()) ++index, offset = 0;
                continue;
            }
            if (offset == 0) {
                file = std::ifstream(s.path, std::ios::binary);
                if (!file) throw core::Error("cannot read " + s.path);
            }
            const std::size_t n = std::min<std::size_t>(room - written, s.size - offset);
            file.read(buffer + written, std::streamsize(n));
            if (std::size_t(file.gcount()) != n) throw core::Error(s.path + " changed while it was being sent");
            written += n;
            offset += n;
            if (offset == s.size) ++index, offset = 0, file.close();
        }
        return written;
    };
    HttpRequest r(endpointOf(remote_, local_, what()), DicomWebUrl::root(remote_.baseUrl) + "/studies");
    r.header("Content-Type: multipart/related; type=\"application/dicom\"; boundary=" + boundary);
    r.header("Accept: application/dicom+json");
    if (job_) r.cancelWith(job_);
    r.postBody(total, source);
    const HttpAnswer a = r.send();
    if (a.status == 409 || a.status < 200 || a.status >= 300)
        throw core::Error(HttpRequest::describeStatus(what() + " (STOW-RS upload)", a.status, a.body));
    return DicomJson::stowOutcome(a.body, what()).stored.size();
}

}  // namespace hvx::dicom
