#include "dicom/TcpListener.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/base/Error.h"

namespace hvx::dicom {

namespace {
/// The IPv4 address `address` names: all interfaces for "" or "0.0.0.0".
in_addr ipv4Of(const std::string& address) {
    in_addr out{};
    out.s_addr = htonl(INADDR_ANY);
    if (address.empty() || ::inet_pton(AF_INET, address.c_str(), &out) == 1) return out;
    addrinfo hints{};
    hints.ai_family = AF_INET;  // DCMTK 3.6.7 reports a caller's address as IPv4 only
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (::getaddrinfo(address.c_str(), nullptr, &hints, &found) != 0 || !found)
        throw core::Error("the listen address '" + address + "' is not an IPv4 address or a host name of one");
    out = reinterpret_cast<sockaddr_in*>(found->ai_addr)->sin_addr;
    ::freeaddrinfo(found);
    return out;
}
}  // namespace

TcpListener::TcpListener(const std::string& address, std::uint16_t port) {
    sockaddr_in where{};
    where.sin_family = AF_INET;
    where.sin_addr = ipv4Of(address);
    where.sin_port = htons(port);
    const std::string name = "port " + std::to_string(port) + (address.empty() ? "" : " of " + address);
    socket_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (socket_ < 0) throw core::Error("cannot open a socket to listen on " + name + ": " + std::strerror(errno));
    const int one = 1;
    ::setsockopt(socket_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);  // restart while old connections linger
    if (::bind(socket_, reinterpret_cast<sockaddr*>(&where), sizeof where) != 0 || ::listen(socket_, 64) != 0) {
        const int error = errno;
        ::close(socket_);
        throw core::Error("cannot listen on " + name + " (" + std::strerror(error) + ")" +
                          (error == EADDRINUSE ? " — is another storage SCP running there?" : ""));
    }
    int pipe[2];
    if (::pipe2(pipe, O_CLOEXEC | O_NONBLOCK) != 0) {
        ::close(socket_);
        throw core::Error(std::string("cannot make the listener's wake-up pipe: ") + std::strerror(errno));
    }
    wakeRead_ = pipe[0];
    wakeWrite_ = pipe[1];
}

TcpListener::~TcpListener() {
    ::close(socket_);
    ::close(wakeRead_);
    ::close(wakeWrite_);
}

int TcpListener::accept(int timeoutMs) {
    pollfd fds[2] = {{socket_, POLLIN, 0}, {wakeRead_, POLLIN, 0}};
    if (::poll(fds, 2, timeoutMs) <= 0 || (fds[1].revents & POLLIN) || !(fds[0].revents & POLLIN)) return -1;
    const int fd = ::accept4(socket_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd == 0) {  // DCMTK takes 0 for "no socket handed over"; never seen, but not wrong either
        const int moved = ::fcntl(fd, F_DUPFD_CLOEXEC, 1);
        ::close(fd);
        return moved;
    }
    return fd;  // -1 when the peer left before it was accepted: the caller polls again
}

void TcpListener::wake() {
    const char byte = 1;
    [[maybe_unused]] const auto n = ::write(wakeWrite_, &byte, 1);  // once is enough: never drained
}

}  // namespace hvx::dicom
