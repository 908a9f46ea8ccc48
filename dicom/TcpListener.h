#pragma once
#include <cstdint>
#include <string>

namespace hvx::dicom {

/// A listening TCP socket of its own, bound to one IPv4 address (or all interfaces), so that the
/// storage SCP can choose where it listens (DCMTK 3.6.7's network binds all interfaces only)
/// and never blocks its accepting thread on a peer: connections are accepted here and handed to
/// DCMTK already open. Threading: accept() from one thread; wake() from any.
class TcpListener {
public:
    /// Binds `address` ("" or "0.0.0.0": all interfaces; a host name resolving to IPv4 is
    /// taken too) and `port`; throws core::Error naming both and the system's reason.
    TcpListener(const std::string& address, std::uint16_t port);
    ~TcpListener();
    TcpListener(const TcpListener&) = delete;
    TcpListener& operator=(const TcpListener&) = delete;
    /// The next connection's socket (close-on-exec), or -1 after `timeoutMs` or once wake() was called.
    int accept(int timeoutMs);
    /// Makes accept() return -1 at once, now and from then on.
    void wake();

private:
    int socket_ = -1;
    int wakeRead_ = -1;
    int wakeWrite_ = -1;
};

}  // namespace hvx::dicom
