#include "dicom/StorageServer.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmnet/dcmtrans.h>
#include <dcmtk/dcmnet/diutil.h>
#include <dcmtk/dcmnet/dul.h>
#include <dcmtk/dcmnet/scpcfg.h>
#include <dcmtk/dcmnet/scpthrd.h>
#include <dcmtk/dcmtls/tlslayer.h>

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <chrono>
#include <cstdio>
#include <future>
#include <map>
#include <mutex>
#include <set>

#include "core/base/Error.h"
#include "dicom/DcmtkSetup.h"
#include "dicom/IncomingStore.h"
#include "dicom/PacsProtocol.h"
#include "dicom/QuickAckTransport.h"
#include "dicom/TcpListener.h"

namespace hvx::dicom {

namespace {
/// What every association's worker shares: all of it safe to use from several threads.
struct Shared {
    IncomingStore* store = nullptr;
    std::function<void(const DicomInstance&)> onStored;
    std::mutex onStoredMutex;  // onStored runs for one instance at a time
    std::string aeTitle;  // ours: the called AE title must be it
    std::vector<std::string> allowed;
    std::map<std::string, std::set<std::string>> hostsOf;  // calling AE -> the addresses it may call from
    std::atomic<std::size_t>* received = nullptr;
    std::uint64_t maxInstanceBytes = 0;
    bool stopped = false;  // under onStoredMutex: no callback once stop() has returned
    std::mutex socketsMutex;
    std::set<int> sockets;  // of the associations being served, for stop()
    bool closing = false;   // under socketsMutex: stop() has cut the sockets
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
            // No room (or no folder): the data set that follows the command is read and
            // dropped, then refused, so the sender knows and the association stays usable.
            const OFCondition c = receiveSTORERequest(req, info.presentationContextID, "/dev/null");
            if (c.bad()) return c;
            return sendSTOREResponse(info.presentationContextID, req, STATUS_STORE_Refused_OutOfResources);
        }
        overCap_ = false;
        const OFCondition c = receiveSTORERequest(req, info.presentationContextID, tmp.c_str());
        // Over the cap: the socket was cut, but what was already in its buffers may have let the
        // data set end; the size of what was written decides too.
        std::error_code ec;
        const auto written = std::filesystem::file_size(tmp, ec);
        if (shared_->maxInstanceBytes > 0 && (overCap_ || (!ec && written > shared_->maxInstanceBytes))) {
            std::remove(tmp.c_str());
            if (socket_ >= 0) ::shutdown(socket_, SHUT_RDWR);
            return c.bad() ? c : DIMSE_RECEIVEFAILED;  // the association ends; the sender learns it failed
        }
        if (c.bad()) {
            std::remove(tmp.c_str());  // interrupted or cut off: nothing half-written stays
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
    /// An instance growing past the cap cuts its association: DCMTK would write it to the end.
    void notifyRECEIVEProgress(const unsigned long byteCount) override {
        if (shared_->maxInstanceBytes == 0 || byteCount <= shared_->maxInstanceBytes) return;
        overCap_ = true;
        if (socket_ >= 0) ::shutdown(socket_, SHUT_RDWR);
    }
    OFBool checkCalledAETitleAccepted(const OFString& calledAE) override {
        return std::string(calledAE.c_str()) == shared_->aeTitle;
    }
    /// DCMTK 3.6.7 passes the *called* presentation address here (scp.cc), so the peer's own
    /// address is asked for.
    OFBool checkCallingHostAccepted(const OFString&) override {
        const auto it = shared_->hostsOf.find(getPeerAETitle().c_str());
        return it == shared_->hostsOf.end() || it->second.count(getPeerIP().c_str()) != 0;
    }
    OFBool checkCallingAETitleAccepted(const OFString& callingAE) override {
        return std::find(shared_->allowed.begin(), shared_->allowed.end(), std::string(callingAE.c_str())) !=
               shared_->allowed.end();
    }

    /// Serves one association to its end; `socket` is a handle on its connection's socket, to cut
    /// an instance over the cap.
    void serve(T_ASC_Association* assoc, int socket) {
        socket_ = socket;
        run(assoc);
        socket_ = -1;
    }

private:
    Shared* shared_;
    int socket_ = -1;       // of the association being served
    bool overCap_ = false;  // the instance being received grew past maxInstanceBytes
};

/// Hands an accepted socket to DCMTK, which takes one from a process-wide variable
/// (dcmExternalSocketHandle) the next time a network receives an association. The handover
/// holds a lock only until DCMTK has taken the socket (its transport layer is asked for the
/// connection), not while the peer sends its A-ASSOCIATE-RQ: so each connection's request is
/// read on its own worker, and a peer that sends half of one holds nothing else.
class Handover : public DcmTransportLayer {
public:
    Handover(DcmTransportLayer* inner, std::unique_lock<std::mutex>& held) : inner_(inner), held_(held) {}
    DcmTransportConnection* createConnection(DcmNativeSocketType socket, OFBool secure) override {
        release();
        taken_ = true;
        return inner_->createConnection(socket, secure);
    }
    /// Lets the next connection's handover go ahead (idempotent).
    void release() {
        if (!held_.owns_lock()) return;
        dcmExternalSocketHandle.set(DCMNET_INVALID_SOCKET);
        held_.unlock();
    }
    /// Whether DCMTK took the socket over (then it closes it).
    bool taken() const { return taken_; }
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }

private:
    DcmTransportLayer* inner_;
    std::unique_lock<std::mutex>& held_;
    bool taken_ = false;
};

/// The listener and its connection workers. The listening socket is Holovox's own (TcpListener:
/// a bind address, and a stop that wakes it at once); each accepted connection is served on a
/// std::thread of its own, from its A-ASSOCIATE-RQ to its release, and joined as soon as it has
/// ended (DCMTK's DcmBaseSCPPool would leave each finished worker's thread behind, scppool.cc
/// 3.6.7). Kept alive by the listener's thread, which joins every worker before it ends.
struct Listening {
    std::shared_ptr<Shared> shared;
    std::shared_ptr<IncomingStore> store;
    DcmSCPConfig config;
    std::unique_ptr<DcmTLSTransportLayer> tls;  // when the node speaks TLS
    std::unique_ptr<DcmTransportLayer> quickAck = makeQuickAckTransport();  // otherwise
    std::unique_ptr<TcpListener> socket;
    std::atomic<bool> stopping{false};
    int maxAssociations = 0;
    std::mutex workersMutex;
    std::map<long, std::thread> workers;  // by connection number
    std::vector<long> finished;           // ended, not joined yet
    int serving = 0;                      // under workersMutex: associations accepted and being served

    /// Accepts connections until `stopping`. At most `maxAssociations` associations are served
    /// at once (more are rejected as busy); beyond twice as many connections, more are closed
    /// at once, so that a flood of connections costs a bounded number of threads.
    void listen() {
        const DcmSharedSCPConfig sharedConfig(config);
        for (long number = 0; !stopping.load(); ++number) {
            const int fd = socket->accept(1000);
            reap();
            if (fd < 0) continue;
            std::lock_guard lock(workersMutex);
            if (stopping.load() || long(workers.size()) >= 2L * maxAssociations) {
                ::close(fd);
                continue;
            }
            workers[number] = std::thread([this, fd, number, &sharedConfig] {
                serveConnection(fd, sharedConfig);
                std::lock_guard done(workersMutex);
                finished.push_back(number);
            });
        }
        std::unique_lock lock(workersMutex);
        while (!workers.empty()) {  // stop() has cut their connections: they end soon
            std::thread w = std::move(workers.begin()->second);
            workers.erase(workers.begin());
            lock.unlock();
            w.join();
            lock.lock();
        }
        finished.clear();
    }

    /// One connection, on its worker: the association request, then the association.
    void serveConnection(int fd, const DcmSharedSCPConfig& sharedConfig) {
        const int cut = registerSocket(fd);  // a second handle on the socket, for stop()
        T_ASC_Association* assoc = nullptr;
        OFCondition c = EC_Normal;
        {
            std::unique_lock<std::mutex> held(Handover::mutex());
            Handover handover(tls ? static_cast<DcmTransportLayer*>(tls.get()) : quickAck.get(), held);
            dcmExternalSocketHandle.set(fd);
            T_ASC_Network* network = nullptr;
            c = ASC_initializeNetwork(NET_ACCEPTOR, 0, int(config.getACSETimeout()), &network);
            if (c.good()) c = ASC_setTransportLayer(network, &handover, 0);
            if (c.good())
                c = ASC_receiveAssociation(network, &assoc, long(config.getMaxReceivePDULength()), nullptr, nullptr,
                                           tls ? OFTrue : OFFalse, DUL_BLOCK, 0);
            handover.release();
            if (!handover.taken()) ::close(fd);
            if (c.good() && !stopping.load()) serveAssociation(assoc, cut, sharedConfig);  // takes it over
            else if (assoc) {
                ASC_dropAssociation(assoc);
                ASC_destroyAssociation(&assoc);
            }
            if (network) ASC_dropNetwork(&network);  // after the association, which uses its layer
        }
        std::lock_guard lock(shared->socketsMutex);
        shared->sockets.erase(cut);
        ::close(cut);
    }

    /// Serves an association to its end, or rejects it as busy when `maxAssociations` are served.
    void serveAssociation(T_ASC_Association* assoc, int cut, const DcmSharedSCPConfig& sharedConfig) {
        {
            std::lock_guard lock(workersMutex);
            if (serving >= maxAssociations) {  // busy: the caller may try again later
                T_ASC_RejectParameters rej{ASC_RESULT_REJECTEDTRANSIENT, ASC_SOURCE_SERVICEPROVIDER_PRESENTATION_RELATED,
                                           ASC_REASON_SP_PRES_LOCALLIMITEXCEEDED};
                ASC_rejectAssociation(assoc, &rej);
                ASC_dropAssociation(assoc);
                ASC_destroyAssociation(&assoc);
                return;
            }
            ++serving;
        }
        {
            Scp scp(shared.get());
            scp.setSharedConfig(sharedConfig);
            scp.serve(assoc, cut);  // DcmThreadSCP takes the association over
        }
        std::lock_guard lock(workersMutex);
        --serving;
    }

    /// A duplicate of the connection's socket, kept until the worker ends, that stop() shuts
    /// down: DCMTK closes its own handle, whose number the system may give to another file.
    int registerSocket(int fd) {
        const int cut = ::fcntl(fd, F_DUPFD_CLOEXEC, 0);
        const int one = 1;  // answer each message at once, not after a delayed ACK
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        std::lock_guard lock(shared->socketsMutex);
        if (cut >= 0) shared->sockets.insert(cut);
        if (shared->closing) ::shutdown(fd, SHUT_RDWR);  // accepted as stop() began
        return cut;
    }

    /// Joins the workers that have ended.
    void reap() {
        std::vector<std::thread> ended;
        {
            std::lock_guard lock(workersMutex);
            for (long n : finished) {
                ended.push_back(std::move(workers[n]));
                workers.erase(n);
            }
            finished.clear();
        }
        for (auto& t : ended) t.join();
    }
};
}  // namespace

struct StorageServer::Impl {
    LocalNode local;
    std::vector<std::string> allowed;
    std::map<std::string, std::vector<std::string>> hostsOf;  // calling AE -> its nodes' hosts
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

void StorageServer::requireHost(const std::string& aeTitle, const std::string& host) {
    if (!host.empty()) impl_->hostsOf[aeTitle].push_back(host);
}

namespace {
/// The receiver's TLS layer (BCP 195), or null when the node has no certificate.
std::unique_ptr<DcmTLSTransportLayer> secureLayer(const LocalNode& local) {
    if (local.tlsCertificate.empty() && local.tlsPrivateKey.empty()) return nullptr;
    auto tls = std::make_unique<DcmTLSTransportLayer>(NET_ACCEPTOR, nullptr, OFTrue);
    OFCondition c = tls->setTLSProfile(TSP_Profile_BCP195);
    if (c.good()) c = tls->activateCipherSuites();
    if (c.good()) c = tls->setPrivateKeyFile(local.tlsPrivateKey.c_str(), DCF_Filetype_PEM);
    if (c.good()) c = tls->setCertificateFile(local.tlsCertificate.c_str(), DCF_Filetype_PEM);
    if (c.bad() || !tls->checkPrivateKeyMatchesCertificate())
        throw core::Error("the storage SCP's TLS certificate or key is unusable (" + local.tlsCertificate + ", " +
                          local.tlsPrivateKey + ")");
    if (!local.tlsTrustedCertificate.empty()) {
        if (tls->addTrustedCertificateFile(local.tlsTrustedCertificate.c_str(), DCF_Filetype_PEM).bad())
            throw core::Error("cannot read the trusted certificate " + local.tlsTrustedCertificate);
        tls->setCertificateVerification(DCV_requireCertificate);
    } else {
        tls->setCertificateVerification(DCV_ignoreCertificate);
    }
    return tls;
}

/// The numeric addresses a host name or address stands for, as DCMTK reports a peer's.
std::set<std::string> addressesOf(const std::string& host) {
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (::getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0)
        throw core::Error("the node host '" + host + "' does not resolve to an address");
    std::set<std::string> out;
    for (addrinfo* a = found; a; a = a->ai_next) {
        char text[INET6_ADDRSTRLEN] = {};
        const void* where = a->ai_family == AF_INET
                                ? static_cast<const void*>(&reinterpret_cast<sockaddr_in*>(a->ai_addr)->sin_addr)
                                : static_cast<const void*>(&reinterpret_cast<sockaddr_in6*>(a->ai_addr)->sin6_addr);
        if (::inet_ntop(a->ai_family, where, text, sizeof text)) out.insert(text);
    }
    ::freeaddrinfo(found);
    return out;
}
}  // namespace

void StorageServer::start() {
    stop();
    auto l = std::make_shared<Listening>();
    l->store = std::make_shared<IncomingStore>(impl_->local.storageDir, impl_->local.minFreeBytes);
    l->shared = std::make_shared<Shared>();
    l->shared->store = l->store.get();
    l->shared->onStored = impl_->onStored;
    l->shared->allowed = impl_->allowed;
    l->shared->aeTitle = impl_->local.aeTitle;
    for (const auto& [ae, hosts] : impl_->hostsOf)
        for (const auto& host : hosts) l->shared->hostsOf[ae].merge(addressesOf(host));
    l->shared->received = &received_;
    l->shared->maxInstanceBytes = impl_->local.maxInstanceBytes;
    l->tls = secureLayer(impl_->local);
    DcmSCPConfig& cfg = l->config;
    cfg.setPort(impl_->local.port);
    cfg.setAETitle(impl_->local.aeTitle.c_str());
    cfg.setDIMSEBlockingMode(DIMSE_NONBLOCKING);
    const Uint32 t = Uint32(std::max(1, impl_->local.timeoutSeconds));
    cfg.setDIMSETimeout(t);
    cfg.setACSETimeout(t);
    cfg.setMaxReceivePDULength(impl_->local.maxPdu);
    cfg.setHostLookupEnabled(OFFalse);
    cfg.setProgressNotificationMode(OFTrue);  // for the instance size cap
    OFList<OFString> basic, storage;
    for (const auto& s : PacsProtocol::basicSyntaxes()) basic.push_back(s.c_str());
    for (const auto& s : PacsProtocol::storageSyntaxes()) storage.push_back(s.c_str());
    cfg.addPresentationContext(UID_VerificationSOPClass, basic);
    for (int i = 0; i < numberOfDcmAllStorageSOPClassUIDs; ++i)
        cfg.addPresentationContext(dcmAllStorageSOPClassUIDs[i], storage);

    l->socket = std::make_unique<TcpListener>(impl_->local.bindAddress, impl_->local.port);  // throws when taken
    l->maxAssociations = kMaxAssociations;
    auto done = std::make_shared<std::promise<void>>();
    impl_->finished = done->get_future().share();
    thread_ = std::thread([l, done] {
        l->listen();
        done->set_value();
    });
    impl_->listening = l;
}

void StorageServer::stop() {
    const auto l = std::move(impl_->listening);
    if (!l) return;
    l->stopping = true;
    {
        std::lock_guard lock(l->shared->onStoredMutex);
        l->shared->stopped = true;
    }
    {
        // Associations still being served (a stalled sender) are cut, so stop() does not wait
        // out their timeouts: their workers see the connection close and end.
        std::lock_guard lock(l->shared->socketsMutex);
        l->shared->closing = true;
        for (int fd : l->shared->sockets) ::shutdown(fd, SHUT_RDWR);
    }
    l->socket->wake();
    // The listener joins its workers, whose connections are cut: it ends at once. It owns what
    // it needs (Listening), so were a worker slow to end, stop() would still return.
    if (impl_->finished.wait_for(std::chrono::seconds(2)) == std::future_status::ready) thread_.join();
    else thread_.detach();
}

}  // namespace hvx::dicom
