#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "dicom/DicomInstance.h"
#include "dicom/PacsNode.h"

namespace hvx::dicom {

/// Holovox's storage SCP: accepts C-ECHO and C-STORE from calling AE titles on its allow-list
/// only, receives each instance bit-preserving into a temporary file and moves it into the
/// storage folder under sanitized UID paths (IncomingStore). It is the C-MOVE destination and
/// the target of pushes from modalities and workstations.
///
/// Threading: start() and stop() from one thread; onStored runs on the server's thread.
class StorageServer {
public:
    StorageServer(LocalNode local, std::vector<std::string> allowedCallers,
                  std::function<void(const DicomInstance&)> onStored);
    ~StorageServer();
    StorageServer(const StorageServer&) = delete;
    StorageServer& operator=(const StorageServer&) = delete;
    /// Opens the port (throws core::Error naming it when it is in use) and serves in the
    /// background until stop().
    void start();
    /// Stops accepting and returns within about a second (an association in progress ends first).
    void stop();
    /// Instances stored so far.
    std::size_t received() const { return received_.load(); }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::thread thread_;
    std::atomic<bool> stopping_{false};
    std::atomic<std::size_t> received_{0};
};

}  // namespace hvx::dicom
