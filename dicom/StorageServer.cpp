#include "dicom/StorageServer.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmnet/dcmtrans.h>
#include <dcmtk/dcmnet/diutil.h>
#include <dcmtk/dcmnet/dul.h>
#include <dcmtk/dcmnet/scppool.h>
#include <dcmtk/dcmnet/scpthrd.h>

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <future>
#include <mutex>
#include <set>

#include "core/base/Error.h"
#include "dicom/DcmtkSetup.h"
#include "dicom/IncomingStore.h"
#include "dicom/PacsProtocol.h"

namespace hvx::dicom {

namespace {
/// What every association's worker shares: all of it safe to use from several threads.
struct Shared {
    IncomingStore* store = nullptr;
    std::function<void(const DicomInstance&)> onStored;
    std::mutex onStoredMutex;  // onStored runs for one instance at a time
    std::vector<std::string> allowed;
    std::atomic<std::size_t>* received = nullptr;
    bool stopped = false;  // under onStoredMutex: no callback once stop() has returned
    std::mutex socketsMutex;
    std::set<int> sockets;  // of the associations being served, for stop()
};

/// The socket of an association's transport connection, which DCMTK keeps protected: it is
/// needed to set TCP_NODELAY and to cut the association on stop().
struct SocketOf : DcmTransportConnection {
    static int of(DcmTransportConnection* c) { return int((c->*(&SocketOf::getSocket))()); }
};

/// One association: C-ECHO, and C-STORE into the IncomingStore.
class Scp : public DcmThreadSCP {
public:
    explicit Scp(Shared* shared) : shared_(shared) {}

    OFCondition handleIncomingCommand(T_DIMSE_Message* msg, const DcmPresentationContextInfo& info) override {
        if (msg->CommandField == DIMSE_C_ECHO_RQ)
            return handleECHORequest(msg->msg.CEchoRQ, info.presentationContextID);
        if (msg->CommandField != DIMSE_C_STORE_RQ) return DcmSCP::handleIncomingCommand(msg, info);
        T_DIMSE_C_StoreRQ& req = msg->msg.CStoreRQ;
        std::string tmp;
        try {
            tmp = shared_->store->temporaryPath();
        } catch (const std::exception&) {
            return sendSTOREResponse(info.presentationContextID, req, STATUS_STORE_Refused_OutOfResources);
        }
        const OFCondition c = receiveSTORERequest(req, info.presentationContextID, tmp.c_str());
        if (c.bad()) {
            std::remove(tmp.c_str());  // interrupted: nothing half-written stays
            return c;
        }
        Uint16 status = STATUS_Success;
        try {
            std::lock_guard lock(shared_->onStoredMutex);
            if (shared_->stopped) {  // the server was stopped while this arrived: not taken
                std::remove(tmp.c_str());
                return sendSTOREResponse(info.presentationContextID, req, STATUS_STORE_Refused_OutOfResources);
            }
            const DicomInstance in = shared_->store->finalize(tmp);
            ++*shared_->received;
            if (shared_->onStored) shared_->onStored(in);
        } catch (const std::exception&) {
            status = STATUS_STORE_Error_CannotUnderstand;
        }
        return sendSTOREResponse(info.presentationContextID, req, status);
    }
    OFBool checkCallingAETitleAccepted(const OFString& callingAE) override {
        return std::find(shared_->allowed.begin(), shared_->allowed.end(), std::string(callingAE.c_str())) !=
               shared_->allowed.end();
    }

protected:
    Shared* shared_;
};

/// DCMTK's pool of association workers (dcmnet/scppool.h), with workers that know the shared
/// state: each accepted association is served on a thread of its own, so a slow or stalled peer
/// holds one worker and nobody else waits for it.
class Pool : public DcmBaseSCPPool {
public:
    explicit Pool(Shared* shared) : shared_(shared) {}

protected:
    struct Worker : public DcmBaseSCPWorker, private Scp {
        explicit Worker(Pool& pool) : DcmBaseSCPWorker(pool), Scp(pool.shared_) {}
        OFCondition setSharedConfig(const DcmSharedSCPConfig& config) override { return Scp::setSharedConfig(config); }
        OFBool busy() override { return Scp::isConnected(); }
        OFCondition workerListen(T_ASC_Association* const assoc) override {
            int fd = -1;
            if (DcmTransportConnection* c = DUL_getTransportConnection(assoc->DULassociation)) fd = SocketOf::of(c);
            if (fd >= 0) {
                const int one = 1;  // answer each DIMSE message at once, not after a delayed ACK
                ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
                std::lock_guard lock(shared_->socketsMutex);
                shared_->sockets.insert(fd);
            }
            const OFCondition result = Scp::run(assoc);
            if (fd >= 0) {
                std::lock_guard lock(shared_->socketsMutex);
                shared_->sockets.erase(fd);
            }
            return result;
        }
    };
    DcmBaseSCPWorker* createSCPWorker() override { return new Worker(*this); }

private:
    Shared* shared_;
};
}  // namespace

/// One run of the listener, kept alive by its thread: stop() may return before a listener
/// stuck reading a half-sent A-ASSOCIATE-RQ notices, and the pool, the shared state and the
/// store must outlive it.
struct Listening {
    std::shared_ptr<Shared> shared;
    std::shared_ptr<IncomingStore> store;
    std::unique_ptr<Pool> pool;
    OFCondition result = EC_Normal;
};

struct StorageServer::Impl {
    LocalNode local;
    std::vector<std::string> allowed;
    std::function<void(const DicomInstance&)> onStored;
    std::shared_ptr<Listening> listening;
    std::shared_future<void> finished;
};

StorageServer::StorageServer(LocalNode local, std::vector<std::string> allowedCallers,
                             std::function<void(const DicomInstance&)> onStored)
    : impl_(std::make_unique<Impl>()) {
    DcmtkSetup::ensure();
    impl_->local = std::move(local);
    IncomingStore check(impl_->local.storageDir);  // the folder can be made: say so now, not at start()
    impl_->allowed = std::move(allowedCallers);
    impl_->onStored = std::move(onStored);
}

StorageServer::~StorageServer() { stop(); }

void StorageServer::start() {
    stop();
    auto l = std::make_shared<Listening>();
    l->store = std::make_shared<IncomingStore>(impl_->local.storageDir);
    l->shared = std::make_shared<Shared>();
    l->shared->store = l->store.get();
    l->shared->onStored = impl_->onStored;
    l->shared->allowed = impl_->allowed;
    l->shared->received = &received_;
    l->pool = std::make_unique<Pool>(l->shared.get());
    Pool& pool = *l->pool;
    pool.setMaxThreads(Uint16(kMaxAssociations));
    DcmSCPConfig& cfg = pool.getConfig();
    cfg.setPort(impl_->local.port);
    cfg.setAETitle(impl_->local.aeTitle.c_str());
    cfg.setConnectionBlockingMode(DUL_NOBLOCK);
    cfg.setConnectionTimeout(1);  // the listener wakes up every second to notice stop()
    cfg.setDIMSEBlockingMode(DIMSE_NONBLOCKING);
    const Uint32 t = Uint32(std::max(1, impl_->local.timeoutSeconds));
    cfg.setDIMSETimeout(t);
    cfg.setACSETimeout(t);
    cfg.setMaxReceivePDULength(ASC_DEFAULTMAXPDU);
    cfg.setHostLookupEnabled(OFFalse);
    OFList<OFString> basic, storage;
    for (const auto& s : PacsProtocol::basicSyntaxes()) basic.push_back(s.c_str());
    for (const auto& s : PacsProtocol::storageSyntaxes()) storage.push_back(s.c_str());
    cfg.addPresentationContext(UID_VerificationSOPClass, basic);
    for (int i = 0; i < numberOfDcmAllStorageSOPClassUIDs; ++i)
        cfg.addPresentationContext(dcmAllStorageSOPClassUIDs[i], storage);

    // The port is opened by the pool's listen(), on its thread, which returns at once when the
    // port cannot be opened and otherwise only after stop().
    auto done = std::make_shared<std::promise<void>>();
    impl_->finished = done->get_future().share();
    thread_ = std::thread([l, done] {
        l->result = l->pool->listen();
        done->set_value();
    });
    if (impl_->finished.wait_for(std::chrono::milliseconds(300)) == std::future_status::ready) {
        thread_.join();
        const std::string why = l->result.bad() ? l->result.text() : "the listener ended";
        throw core::Error("cannot listen on port " + std::to_string(impl_->local.port) + " (" + why +
                          ") — is another storage SCP running there?");
    }
    impl_->listening = l;
}

void StorageServer::stop() {
    const auto l = std::move(impl_->listening);
    if (!l) return;
    l->pool->stopAfterCurrentAssociations();
    {
        std::lock_guard lock(l->shared->onStoredMutex);
        l->shared->stopped = true;
    }
    {
        // Associations still being served (a stalled sender) are cut, so stop() does not wait
        // out their timeouts: their workers see the connection close and end.
        std::lock_guard lock(l->shared->socketsMutex);
        for (int fd : l->shared->sockets) ::shutdown(fd, SHUT_RDWR);
    }
    // A listener reading a half-sent association request ends within the socket read timeout;
    // it owns what it needs (Listening), so it may finish after stop() has returned.
    if (impl_->finished.wait_for(std::chrono::seconds(1)) == std::future_status::ready) thread_.join();
    else thread_.detach();
}

}  // namespace hvx::dicom
