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

/// Holovox's storage SCP: accepts C-ECHO and C-STORE called to its own AE title, from calling
/// AE titles on its allow-list only (and from their node's address when it has one), receives each instance bit-preserving into a temporary file and moves it into the
/// storage folder under sanitized UID paths (IncomingStore). It is the C-MOVE destination and
/// the target of pushes from modalities and workstations. Associations are served at once, up
/// to kMaxAssociations, each on a worker thread of its own (joined when it ends), with
/// TCP_NODELAY; below the free-space floor instances are refused as Out of Resources, and one
/// larger than the cap is cut off (LocalNode::minFreeBytes, maxInstanceBytes). It listens on
/// LocalNode::bindAddress (all interfaces when empty) with a socket of its own; each connection
/// is served on its own worker from its A-ASSOCIATE-RQ on, so a peer that sends half a request,
/// or stalls inside an association, holds only its own worker (for kRequestTimeoutSeconds or
/// the DIMSE timeout), never the listener.
///
/// Threading: start() and stop() from one thread; onStored runs on the workers' threads, one
/// instance at a time.
class StorageServer {
public:
    StorageServer(LocalNode local, std::vector<std::string> allowedCallers,
                  std::function<void(const DicomInstance&)> onStored);
    ~StorageServer();
    StorageServer(const StorageServer&) = delete;
    StorageServer& operator=(const StorageServer&) = delete;
    /// Accepts `aeTitle` only from the addresses `host` resolves to (a node's entry in the node
    /// table); an allowed AE title without such an entry is accepted from anywhere. Before start().
    void requireHost(const std::string& aeTitle, const std::string& host);
    /// Opens the port on the bind address (throws core::Error naming it when it is in use or
    /// the address is not this machine's, or a required host that does not resolve) and serves
    /// in the background until stop().
    void start();
    /// Stops accepting, cuts the connections in progress and returns at once (within two
    /// seconds at worst).
    void stop();
    static constexpr int kMaxAssociations = 16;
    /// How long a connection that sends no complete A-ASSOCIATE-RQ holds its worker: DcmtkSetup's
    /// socket read timeout.
    static constexpr int kRequestTimeoutSeconds = 10;
    /// Instances stored so far.
    std::size_t received() const { return received_.load(); }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::thread thread_;
    std::atomic<std::size_t> received_{0};
};

}  // namespace hvx::dicom
