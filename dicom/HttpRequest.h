#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/base/JobContext.h"

namespace hvx::dicom {

/// How to reach and authenticate with an HTTP service (a DICOMweb node).
struct HttpEndpoint {
    std::string what;         ///< how errors name the service ("DICOMweb node 'x' (http://...)")
    std::string bearerToken;  ///< "Authorization: Bearer ..." when not empty
    std::string username, password;  ///< basic authentication when username is not empty
    bool tlsVerify = true;    ///< https: verify the certificate chain and the host name
    int timeoutSeconds = 30;  ///< connect timeout, and the longest a transfer may stall
};

/// The answer to one request: its status and the headers Holovox reads.
struct HttpAnswer {
    long status = 0;
    std::string contentType;
    std::string body;  ///< only when no body sink was given (capped, see HttpRequest::send)
};

/// One HTTP request on libcurl: GET or POST, the body streamed to a sink as it arrives (or kept
/// whole up to a cap), a request body streamed from a source, cancellation by a job, and every
/// transport failure turned into a sentence that says what to check (host, TLS, timeout).
/// HTTP statuses are returned, not thrown: the caller knows what a 404 means for it.
///
/// Threading: one object per request; any number of requests may run on different threads.
class HttpRequest {
public:
    HttpRequest(HttpEndpoint endpoint, std::string url);
    void header(const std::string& line) { headers_.push_back(line); }
    /// Streams a successful (2xx) response body to `sink`, after `start` was told its content
    /// type. An exception thrown by either stops the transfer and is rethrown by send(). The
    /// body of an error status is kept instead (see HttpAnswer::body), for its message.
    void onBody(std::function<void(const std::string& contentType)> start,
                std::function<void(const char*, std::size_t)> sink) {
        start_ = std::move(start);
        sink_ = std::move(sink);
    }
    /// Makes it a POST of `size` bytes read from `source` (fills the buffer, returns bytes
    /// written, 0 at the end; an exception it throws stops the transfer and is rethrown).
    void postBody(std::uint64_t size, std::function<std::size_t(char*, std::size_t)> source);
    void cancelWith(const core::JobContext* job) { job_ = job; }
    /// Sends the request and waits for the whole answer. Without a sink the body is kept, up
    /// to `maxBody` bytes (more is an error: a hostile server cannot exhaust memory). Throws
    /// core::Error for transport failures, core::Cancelled when the job was cancelled.
    HttpAnswer send(std::size_t maxBody = std::size_t(64) << 20);
    /// The sentence for an HTTP error status of `what` (401/403: credentials, 404, 413, 507...),
    /// with the start of the server's own message when it sent one.
    static std::string describeStatus(const std::string& what, long status, const std::string& body);

private:
    HttpEndpoint endpoint_;
    std::string url_;
    std::vector<std::string> headers_;
    std::function<void(const std::string&)> start_;
    std::function<void(const char*, std::size_t)> sink_;
    std::function<std::size_t(char*, std::size_t)> source_;
    std::uint64_t postSize_ = 0;
    bool post_ = false;
    const core::JobContext* job_ = nullptr;
};

}  // namespace hvx::dicom
