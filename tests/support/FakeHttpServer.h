#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

namespace hvx::test {

/// A tiny HTTP server on a free loopback port for tests of what a broken or hostile server
/// does to a client: each request (headers, and its body when it gives a Content-Length) is
/// answered by `respond`, which writes whatever raw bytes it likes to the socket, may stall,
/// and returns; the connection is then closed. Stopped (and its thread joined) on destruction.
class FakeHttpServer {
public:
    /// Writes the answer to `socket` for `request` (the request line and headers).
    using Responder = std::function<void(int socket, const std::string& request)>;
    explicit FakeHttpServer(Responder respond);
    ~FakeHttpServer();
    FakeHttpServer(const FakeHttpServer&) = delete;
    FakeHttpServer& operator=(const FakeHttpServer&) = delete;

    std::string url() const { return "http://127.0.0.1:" + std::to_string(port_) + "/dicom-web"; }
    int requests() const { return requests_; }
    /// Writes all of `bytes`; false when the client went away.
    static bool write(int socket, const std::string& bytes);
    /// A whole answer: status line, Content-Type, Content-Length, body.
    static std::string answer(int status, const std::string& contentType, const std::string& body);

private:
    void serve();
    Responder respond_;
    int listener_ = -1;
    std::uint16_t port_ = 0;
    std::atomic<bool> stop_{false};
    std::atomic<int> requests_{0};
    std::thread thread_;
};

}  // namespace hvx::test
