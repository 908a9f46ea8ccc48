#include "dicom/StorageServer.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmnet/diutil.h>
#include <dcmtk/dcmnet/scp.h>

#include <algorithm>
#include <cstdio>

#include "core/base/Error.h"
#include "dicom/DcmtkSetup.h"
#include "dicom/IncomingStore.h"
#include "dicom/PacsProtocol.h"

namespace hvx::dicom {

namespace {
class Scp : public DcmSCP {
public:
    IncomingStore* store = nullptr;
    std::function<void(const DicomInstance&)> onStored;
    std::vector<std::string> allowed;
    std::atomic<bool>* stopping = nullptr;
    std::atomic<std::size_t>* received = nullptr;

    OFCondition handleIncomingCommand(T_DIMSE_Message* msg, const DcmPresentationContextInfo& info) override {
        if (msg->CommandField == DIMSE_C_ECHO_RQ)
            return handleECHORequest(msg->msg.CEchoRQ, info.presentationContextID);
        if (msg->CommandField != DIMSE_C_STORE_RQ) return DcmSCP::handleIncomingCommand(msg, info);
        T_DIMSE_C_StoreRQ& req = msg->msg.CStoreRQ;
        const std::string tmp = store->temporaryPath();
        const OFCondition c = receiveSTORERequest(req, info.presentationContextID, tmp.c_str());
        if (c.bad()) {
            std::remove(tmp.c_str());  // interrupted: nothing half-written stays
            return c;
        }
        Uint16 status = STATUS_Success;
        try {
            const DicomInstance in = store->finalize(tmp);
            ++*received;
            if (onStored) onStored(in);
        } catch (const std::exception&) {
            status = STATUS_STORE_Error_CannotUnderstand;
        }
        return sendSTOREResponse(info.presentationContextID, req, status);
    }
    OFBool checkCallingAETitleAccepted(const OFString& callingAE) override {
        return std::find(allowed.begin(), allowed.end(), std::string(callingAE.c_str())) != allowed.end();
    }
    OFBool stopAfterConnectionTimeout() override { return stopping->load(); }
    OFBool stopAfterCurrentAssociation() override { return stopping->load(); }
};
}  // namespace

struct StorageServer::Impl {
    LocalNode local;
    std::unique_ptr<IncomingStore> store;
    Scp scp;
};

StorageServer::StorageServer(LocalNode local, std::vector<std::string> allowedCallers,
                             std::function<void(const DicomInstance&)> onStored)
    : impl_(std::make_unique<Impl>()) {
    DcmtkSetup::ensure();
    impl_->local = std::move(local);
    impl_->store = std::make_unique<IncomingStore>(impl_->local.storageDir);
    Scp& scp = impl_->scp;
    scp.store = impl_->store.get();
    scp.onStored = std::move(onStored);
    scp.allowed = std::move(allowedCallers);
    scp.stopping = &stopping_;
    scp.received = &received_;
    DcmSCPConfig& cfg = scp.getConfig();
    cfg.setPort(impl_->local.port);
    cfg.setAETitle(impl_->local.aeTitle.c_str());
    cfg.setConnectionBlockingMode(DUL_NOBLOCK);
    cfg.setConnectionTimeout(1);  // wake up every second to notice stop()
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
}

StorageServer::~StorageServer() { stop(); }

void StorageServer::start() {
    stopping_ = false;
    const OFCondition c = impl_->scp.openListenPort();
    if (c.bad())
        throw core::Error("cannot listen on port " + std::to_string(impl_->local.port) + " (" + c.text() +
                          ") — is another storage SCP running there?");
    thread_ = std::thread([this] { impl_->scp.acceptAssociations(); });
}

void StorageServer::stop() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
}

}  // namespace hvx::dicom
