#include "tests/support/FakeHttpServer.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>

namespace hvx::test {

FakeHttpServer::FakeHttpServer(Responder respond) : respond_(std::move(respond)) {
    listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(listener_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(listener_, 8) != 0)
        throw std::runtime_error("FakeHttpServer: cannot listen");
    socklen_t len = sizeof a;
    ::getsockname(listener_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] { serve(); });
}

FakeHttpServer::~FakeHttpServer() {
    stop_ = true;
    thread_.join();
    ::close(listener_);
}

bool FakeHttpServer::write(int socket, const std::string& bytes) {
    std::size_t at = 0;
    while (at < bytes.size()) {
        const ssize_t n = ::send(socket, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
        if (n <= 0) return false;
        at += std::size_t(n);
    }
    return true;
}

std::string FakeHttpServer::answer(int status, const std::string& contentType, const std::string& body) {
    return "HTTP/1.1 " + std::to_string(status) + " X\r\nContent-Type: " + contentType +
           "\r\nContent-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
}

void FakeHttpServer::serve() {
    while (!stop_) {
        pollfd p{listener_, POLLIN, 0};
        if (::poll(&p, 1, 50) <= 0) continue;
        const int s = ::accept(listener_, nullptr, nullptr);
        if (s < 0) continue;
        std::string request;
        char buf[65536];
        std::size_t bodyLeft = 0;
        bool headersDone = false;
        while (!headersDone || bodyLeft > 0) {
            pollfd q{s, POLLIN, 0};
            if (::poll(&q, 1, 5000) <= 0) break;
            const ssize_t n = ::recv(s, buf, sizeof buf, 0);
            if (n <= 0) break;
            if (headersDone) {
                bodyLeft -= std::min(bodyLeft, std::size_t(n));
                continue;
            }
            request.append(buf, std::size_t(n));
            const auto end = request.find("\r\n\r\n");
            if (end == std::string::npos) continue;
            headersDone = true;
            std::size_t length = 0;
            for (const char* key : {"Content-Length: ", "content-length: "})
                if (const auto at = request.find(key); at != std::string::npos && at < end)
                    length = std::stoul(request.substr(at + 16));
            const std::size_t got = request.size() - (end + 4);
            bodyLeft = length > got ? length - got : 0;
            request.resize(end);
        }
        ++requests_;
        respond_(s, request);
        ::shutdown(s, SHUT_RDWR);
        ::close(s);
    }
}

}  // namespace hvx::test
