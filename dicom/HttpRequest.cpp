#include "dicom/HttpRequest.h"

#include <curl/curl.h>

#include <algorithm>
#include <exception>
#include <memory>
#include <mutex>

#include "core/base/Error.h"

namespace hvx::dicom {

namespace {
void ensureCurl() {
    static std::once_flag once;
    std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
}

struct Transfer {
    CURL* handle = nullptr;
    std::function<void(const std::string&)>* start = nullptr;
    std::function<void(const char*, std::size_t)>* sink = nullptr;
    bool started = false, streaming = false;
    std::string body;
    std::size_t maxBody = 0;
    bool tooLarge = false;
    std::exception_ptr failure;  // thrown by a sink or source: rethrown after the transfer
    std::function<std::size_t(char*, std::size_t)>* source = nullptr;
    const core::JobContext* job = nullptr;
};

std::size_t onWrite(char* data, std::size_t size, std::size_t count, void* user) {
    auto* t = static_cast<Transfer*>(user);
    const std::size_t n = size * count;
    if (!t->started) {  // the status is known once the body begins
        t->started = true;
        long status = 0;
        curl_easy_getinfo(t->handle, CURLINFO_RESPONSE_CODE, &status);
        t->streaming = *t->sink && status >= 200 && status < 300;
        if (!t->streaming && *t->sink) t->maxBody = std::min<std::size_t>(t->maxBody, 64 << 10);
        const char* type = nullptr;
        try {
            if (t->streaming && *t->start)
                (*t->start)(curl_easy_getinfo(t->handle, CURLINFO_CONTENT_TYPE, &type) == CURLE_OK && type ? type : "");
        } catch (...) {
            t->failure = std::current_exception();
            return 0;
        }
    }
    if (t->streaming) {
        try {
            (*t->sink)(data, n);
        } catch (...) {
            t->failure = std::current_exception();
            return 0;
        }
        return n;
    }
    if (t->body.size() + n > t->maxBody) {
        if (*t->sink) return n;  // an error page: its start is enough
        t->tooLarge = true;
        return 0;
    }
    t->body.append(data, n);
    return n;
}

std::size_t onRead(char* buffer, std::size_t size, std::size_t count, void* user) {
    auto* t = static_cast<Transfer*>(user);
    try {
        return (*t->source)(buffer, size * count);
    } catch (...) {
        t->failure = std::current_exception();
        return CURL_READFUNC_ABORT;
    }
}

int onProgress(void* user, curl_off_t, curl_off_t, curl_off_t, curl_off_t) {
    const auto* t = static_cast<Transfer*>(user);
    return t->job && t->job->cancelled() ? 1 : 0;
}

std::string transportFailure(const std::string& what, CURLcode code, const char* detail, int timeout) {
    const std::string d = detail && *detail ? std::string(" (") + detail + ")" : std::string();
    switch (code) {
        case CURLE_COULDNT_RESOLVE_HOST:
            return what + ": the host name is unknown" + d + "; check the URL";
        case CURLE_COULDNT_CONNECT:
            return what + ": cannot connect" + d + "; check the URL's host and port, and that the server runs";
        case CURLE_OPERATION_TIMEDOUT:
            return what + ": no answer for " + std::to_string(timeout) + " s" + d +
                   "; the server stalled or is overloaded (the timeout is in the PACS settings)";
        case CURLE_PEER_FAILED_VERIFICATION:
        case CURLE_SSL_CACERT_BADFILE:
        case CURLE_SSL_CONNECT_ERROR:
        case CURLE_SSL_CERTPROBLEM:
            return what + ": TLS failure" + d +
                   "; the server's certificate was not accepted (check its issuer and that it names this host)";
        case CURLE_UNSUPPORTED_PROTOCOL:
        case CURLE_URL_MALFORMAT:
            return what + ": the URL is not a usable http or https address" + d;
        case CURLE_GOT_NOTHING:
        case CURLE_RECV_ERROR:
        case CURLE_SEND_ERROR:
        case CURLE_PARTIAL_FILE:
            return what + ": the connection broke off in the middle of the answer" + d;
        default:
            return what + ": " + curl_easy_strerror(code) + d;
    }
}
}  // namespace

HttpRequest::HttpRequest(HttpEndpoint endpoint, std::string url) : endpoint_(std::move(endpoint)), url_(std::move(url)) {}

void HttpRequest::postBody(std::uint64_t size, std::function<std::size_t(char*, std::size_t)> source) {
    post_ = true;
    postSize_ = size;
    source_ = std::move(source);
}

HttpAnswer HttpRequest::send(std::size_t maxBody) {
    ensureCurl();
    std::unique_ptr<CURL, decltype(&curl_easy_cleanup)> curl(curl_easy_init(), curl_easy_cleanup);
    if (!curl) throw core::Error(endpoint_.what + ": cannot start an HTTP transfer (libcurl)");
    CURL* h = curl.get();
    Transfer t;
    t.handle = h;
    t.start = &start_;
    t.sink = &sink_;
    t.maxBody = maxBody;
    t.source = &source_;
    t.job = job_;
    char error[CURL_ERROR_SIZE] = {};
    curl_easy_setopt(h, CURLOPT_URL, url_.c_str());
    curl_easy_setopt(h, CURLOPT_PROTOCOLS_STR, "http,https");
    curl_easy_setopt(h, CURLOPT_ERRORBUFFER, error);
    curl_easy_setopt(h, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(h, CURLOPT_TCP_NODELAY, 1L);
    curl_easy_setopt(h, CURLOPT_CONNECTTIMEOUT, long(std::max(1, endpoint_.timeoutSeconds)));
    // A transfer may take long; one that moves nothing for the timeout has stalled.
    curl_easy_setopt(h, CURLOPT_LOW_SPEED_LIMIT, 1L);
    curl_easy_setopt(h, CURLOPT_LOW_SPEED_TIME, long(std::max(1, endpoint_.timeoutSeconds)));
    // Bodies arrive in reads of up to 512 KiB rather than libcurl's 16 KiB: a WADO-RS of 500
    // CT instances (66 MB) made 4,000 reads and as many polls.
    curl_easy_setopt(h, CURLOPT_BUFFERSIZE, 512L * 1024L);
    curl_easy_setopt(h, CURLOPT_WRITEFUNCTION, onWrite);
    curl_easy_setopt(h, CURLOPT_WRITEDATA, &t);
    curl_easy_setopt(h, CURLOPT_NOPROGRESS, 0L);
    curl_easy_setopt(h, CURLOPT_XFERINFOFUNCTION, onProgress);
    curl_easy_setopt(h, CURLOPT_XFERINFODATA, &t);
    curl_easy_setopt(h, CURLOPT_SSL_VERIFYPEER, endpoint_.tlsVerify ? 1L : 0L);
    curl_easy_setopt(h, CURLOPT_SSL_VERIFYHOST, endpoint_.tlsVerify ? 2L : 0L);
    if (!endpoint_.username.empty()) {
        curl_easy_setopt(h, CURLOPT_HTTPAUTH, long(CURLAUTH_BASIC));
        curl_easy_setopt(h, CURLOPT_USERNAME, endpoint_.username.c_str());
        curl_easy_setopt(h, CURLOPT_PASSWORD, endpoint_.password.c_str());
    }
    std::vector<std::string> lines = headers_;
    if (!endpoint_.bearerToken.empty()) lines.push_back("Authorization: Bearer " + endpoint_.bearerToken);
    if (post_) lines.push_back("Expect:");  // send the body at once, without a 100-continue round trip
    std::unique_ptr<curl_slist, decltype(&curl_slist_free_all)> list(nullptr, curl_slist_free_all);
    for (const auto& l : lines) list.reset(curl_slist_append(list.release(), l.c_str()));
    curl_easy_setopt(h, CURLOPT_HTTPHEADER, list.get());
    if (post_) {
        curl_easy_setopt(h, CURLOPT_POST, 1L);
        curl_easy_setopt(h, CURLOPT_POSTFIELDSIZE_LARGE, curl_off_t(postSize_));
        curl_easy_setopt(h, CURLOPT_READFUNCTION, onRead);
        curl_easy_setopt(h, CURLOPT_READDATA, &t);
    }
    const CURLcode code = curl_easy_perform(h);
    if (code == CURLE_ABORTED_BY_CALLBACK && job_ && job_->cancelled()) throw core::Cancelled();
    if (t.tooLarge)
        throw core::Error(endpoint_.what + ": the answer is larger than " + std::to_string(maxBody >> 20) +
                          " MiB, more than any query answer should be; refused");
    if (t.failure) std::rethrow_exception(t.failure);
    if (code != CURLE_OK)
        throw core::Error(transportFailure(endpoint_.what, code, error, endpoint_.timeoutSeconds));
    HttpAnswer a;
    curl_easy_getinfo(h, CURLINFO_RESPONSE_CODE, &a.status);
    const char* type = nullptr;
    if (curl_easy_getinfo(h, CURLINFO_CONTENT_TYPE, &type) == CURLE_OK && type) a.contentType = type;
    a.body = std::move(t.body);
    return a;
}

std::string HttpRequest::describeStatus(const std::string& what, long status, const std::string& body) {
    std::string why;
    switch (status) {
        case 400: why = "the server did not understand the request (HTTP 400)"; break;
        case 401:
        case 403:
            why = "the server refused our credentials (HTTP " + std::to_string(status) +
                  "); check the node's bearer token or user name and password";
            break;
        case 404: why = "not found (HTTP 404): no such study or series there, or the URL is not the DICOMweb root"; break;
        case 406: why = "the server cannot send what was asked for (HTTP 406)"; break;
        case 409: why = "the server refused every instance (HTTP 409)"; break;
        case 413: why = "the server refused the upload as too large (HTTP 413); send fewer files at once"; break;
        case 415: why = "the server does not take this media type (HTTP 415)"; break;
        case 503: why = "the server is busy or down for maintenance (HTTP 503); try again later"; break;
        case 507: why = "the server's storage is full (HTTP 507)"; break;
        default: why = "HTTP " + std::to_string(status); break;
    }
    std::string said = body.substr(0, 200);
    std::replace_if(said.begin(), said.end(), [](char c) { return c == '\n' || c == '\r' || c == '\t'; }, ' ');
    said.erase(std::remove_if(said.begin(), said.end(), [](char c) { return (unsigned char)c < 0x20; }), said.end());
    return what + ": " + why + (said.find_first_not_of(' ') != std::string::npos ? " — the server said: " + said : "");
}

}  // namespace hvx::dicom
