#include "dicom/PacsClient.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmnet/diutil.h>
#include <dcmtk/dcmnet/scu.h>
#include <dcmtk/dcmtls/tlslayer.h>
#include <openssl/ssl.h>
#include <openssl/x509_vfy.h>
#include <openssl/x509v3.h>

#include <arpa/inet.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <mutex>
#include <thread>
#include <set>
#include <tuple>

#include "core/base/Error.h"
#include "dicom/DcmtkSetup.h"
#include "dicom/DatasetText.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomWebClient.h"
#include "dicom/IncomingFiler.h"
#include "dicom/IncomingStore.h"
#include "dicom/PacsProtocol.h"
#include "dicom/QuickAckTransport.h"

namespace hvx::dicom {

namespace {
std::string text(DcmItem* ds, const DcmTagKey& key) {
    OFString v;
    if (ds && ds->findAndGetOFStringArray(key, v).good()) return v.c_str();
    return {};
}
int integer(DcmItem* ds, const DcmTagKey& key) {
    Sint32 v = 0;
    return ds && ds->findAndGetSint32(key, v).good() ? int(v) : 0;
}

QueryResult toResult(DcmDataset* ds, QueryLevel level) {
    // An archive answers in the character set its data was stored in (Orthanc's default is
    // Latin-1): read as UTF-8, as files are (a Latin-1 name had shown as invalid UTF-8).
    if (ds) DatasetText::toUtf8(*ds);
    QueryResult r;
    r.level = level;
    r.patientName = text(ds, DCM_PatientName);
    r.patientId = text(ds, DCM_PatientID);
    r.patientBirthDate = text(ds, DCM_PatientBirthDate);
    r.studyUid = text(ds, DCM_StudyInstanceUID);
    r.studyDate = text(ds, DCM_StudyDate);
    r.studyTime = text(ds, DCM_StudyTime);
    r.studyDescription = text(ds, DCM_StudyDescription);
    r.accessionNumber = text(ds, DCM_AccessionNumber);
    r.modalitiesInStudy = text(ds, DCM_ModalitiesInStudy);
    r.seriesUid = text(ds, DCM_SeriesInstanceUID);
    r.seriesDescription = text(ds, DCM_SeriesDescription);
    r.modality = text(ds, DCM_Modality);
    r.seriesNumber = integer(ds, DCM_SeriesNumber);
    r.instanceNumber = integer(ds, DCM_InstanceNumber);
    r.sopInstanceUid = text(ds, DCM_SOPInstanceUID);
    r.numberOfInstances = integer(ds, level == QueryLevel::Study ? DCM_NumberOfStudyRelatedInstances
                                                                  : DCM_NumberOfSeriesRelatedInstances);
    return r;
}

// DcmSCU with Holovox's handlers: streaming C-FIND answers, sub-operation progress, and C-GET
// instances received bit-preserving into the IncomingStore.
/// The last certificate verification error on this thread (the TLS handshake runs on the
/// thread that connects), so that a refused certificate is explained in words.
thread_local int lastVerifyError = X509_V_OK;

int recordVerifyError(int ok, X509_STORE_CTX* store) {
    if (!ok) lastVerifyError = X509_STORE_CTX_get_error(store);
    return ok;
}

bool isIpAddress(const std::string& host) {
    unsigned char buf[16];
    return ::inet_pton(AF_INET, host.c_str(), buf) == 1 || ::inet_pton(AF_INET6, host.c_str(), buf) == 1;
}

class Scu : public DcmSCU {
public:
    std::function<bool(const QueryResult&)> onFind;
    QueryLevel level = QueryLevel::Study;
    bool cancelled = false;
    std::size_t delivered = 0;
    Uint16 finalStatus = 0;
    IncomingStore* store = nullptr;
    /// C-GET: files each received instance while the next ones arrive (the C-STORE is answered
    /// once the instance is written; the archive keeps the original, and an instance is
    /// reported, and so indexed, only once flushed and in place).
    IncomingFiler* filer = nullptr;
    std::function<void(const DicomInstance&)> onStored;
    std::function<void(const RetrieveProgress&)> onProgress;
    RetrieveProgress progress;
    std::string storeError;
    const core::JobContext* job = nullptr;  // cancels retrieves
    bool cancelSent = false;
    bool jobCancelled() const { return job && job->cancelled(); }
    /// Sends C-CANCEL once when the job was cancelled.
    void cancelIfAsked(T_ASC_PresentationContextID presID) {
        if (!jobCancelled() || cancelSent) return;
        cancelSent = true;
        sendCANCELRequest(presID);
    }

    OFCondition handleFINDResponse(const T_ASC_PresentationContextID presID, QRResponse* r,
                                   OFBool& waitForNextResponse) override {
        if (r && DICOM_PENDING_STATUS(r->m_status) && r->m_dataset) {
            waitForNextResponse = OFTrue;
            if (!cancelled) {
                ++delivered;
                if (onFind && !onFind(toResult(r->m_dataset, level))) {
                    cancelled = true;
                    sendCANCELRequest(presID);
                }
            }
            return EC_Normal;
        }
        if (r) finalStatus = r->m_status;
        return DcmSCU::handleFINDResponse(presID, r, waitForNextResponse);
    }
    void track(RetrieveResponse* r) {
        if (!r) return;
        finalStatus = r->m_status;
        progress.remaining = r->m_numberOfRemainingSubops;
        progress.completed = r->m_numberOfCompletedSubops;
        progress.failed = r->m_numberOfFailedSubops;
        progress.warning = r->m_numberOfWarningSubops;
        if (onProgress) onProgress(progress);
    }
    OFCondition handleCGETResponse(const T_ASC_PresentationContextID presID, RetrieveResponse* r,
                                   OFBool& continueSession) override {
        track(r);
        cancelIfAsked(presID);
        return DcmSCU::handleCGETResponse(presID, r, continueSession);
    }
    OFCondition handleMOVEResponse(const T_ASC_PresentationContextID presID, RetrieveResponse* r,
                                   OFBool& waitForNextResponse) override {
        track(r);
        cancelIfAsked(presID);
        return DcmSCU::handleMOVEResponse(presID, r, waitForNextResponse);
    }
    OFCondition handleSTORERequestFile(T_ASC_PresentationContextID* presID, const OFString&,
                                       T_DIMSE_C_StoreRQ* request) override {
        // DCMTK would name the file after the (untrusted) SOP Instance UID; we receive into a
        // temporary name and let the IncomingStore place it.
        if (!store || !filer) return EC_IllegalCall;
        if (jobCancelled()) {  // the peer goes on sending: the association is aborted
            storeError = "cancelled";
            return EC_IllegalCall;
        }
        std::string tmp;
        try {
            tmp = store->temporaryPath();
        } catch (const core::Error& e) {  // no room: the retrieve stops and says why
            storeError = e.what();
            return EC_IllegalCall;
        }
        OFCondition c = DcmSCU::handleSTORERequestFile(presID, tmp.c_str(), request);
        if (c.bad()) return c;
        try {
            filer->submit(tmp, [this](const DicomInstance& in) { stored(in); });
        } catch (const core::Error& e) {
            storeError = e.what();
            return EC_IllegalCall;
        }
        return c;
    }
    /// Counts and reports an instance in place (on the receiving thread).
    void stored(const DicomInstance& in) {
        ++progress.received;
        if (onStored) onStored(in);
    }
    void notifyInstanceStored(const OFString&, const OFString&, const OFString&) const override {}
    /// DcmSCU keeps this protected; call after initNetwork().
    OFCondition secureWith(DcmTransportLayer* layer) { return useSecureConnection(layer); }
};
}  // namespace

struct PacsClient::Impl {
    LocalNode local;
    PacsNode remote;
    const core::JobContext* job = nullptr;
    std::unique_ptr<DicomWebClient> web;  // a DICOMweb node: every operation goes to it
    std::unique_ptr<DcmTransportLayer> quickAck = makeQuickAckTransport();  // plain TCP; outlives them
    std::unique_ptr<DcmTLSTransportLayer> tls;  // outlives the association it secures

    void secure(Scu& scu) {
        if (remote.tlsTrustedCertificate.empty())
            throw core::Error(where() + ": a TLS node needs tlsTrustedCertificate (the PEM file of the CA that signs "
                                        "its certificate)");
        tls = std::make_unique<DcmTLSTransportLayer>(NET_REQUESTOR, nullptr, OFTrue);
        OFCondition c = tls->setTLSProfile(TSP_Profile_BCP195);
        if (c.good()) c = tls->activateCipherSuites();
        if (c.good()) c = tls->addTrustedCertificateFile(remote.tlsTrustedCertificate.c_str(), DCF_Filetype_PEM);
        if (c.bad())
            throw core::Error(where() + ": cannot set up TLS with " + remote.tlsTrustedCertificate + " (" + c.text() + ")");
        tls->setCertificateVerification(DCV_requireCertificate);
        // The chain alone is not enough: the certificate must name the host we dialled (a DNS or
        // IP subjectAltName), as a browser checks, or any certificate the CA signed would do.
        SSL_CTX* native = tls->getNativeHandle();
        X509_VERIFY_PARAM* param = SSL_CTX_get0_param(native);
        X509_VERIFY_PARAM_set_hostflags(param, X509_CHECK_FLAG_NO_PARTIAL_WILDCARDS);
        const int named = isIpAddress(remote.host) ? X509_VERIFY_PARAM_set1_ip_asc(param, remote.host.c_str())
                                                   : X509_VERIFY_PARAM_set1_host(param, remote.host.c_str(), 0);
        if (named != 1) throw core::Error(where() + ": '" + remote.host + "' cannot be checked against a TLS certificate");
        SSL_CTX_set_verify(native, SSL_VERIFY_PEER | SSL_VERIFY_FAIL_IF_NO_PEER_CERT, recordVerifyError);
        lastVerifyError = X509_V_OK;
        if (!remote.tlsCertificate.empty()) {
            c = tls->setPrivateKeyFile(remote.tlsPrivateKey.c_str(), DCF_Filetype_PEM);
            if (c.good()) c = tls->setCertificateFile(remote.tlsCertificate.c_str(), DCF_Filetype_PEM);
            if (c.bad() || !tls->checkPrivateKeyMatchesCertificate())
                throw core::Error(where() + ": our TLS certificate or key is unusable (" + remote.tlsCertificate + ")");
        }
        c = scu.secureWith(tls.get());
        if (c.bad()) throw core::Error(where() + ": cannot use TLS (" + std::string(c.text()) + ")");
    }

    std::string where() const {
        return "PACS '" + remote.name + "' (AE '" + remote.aeTitle + "' at " + remote.host + ":" +
               std::to_string(remote.port) + ")";
    }

    using Context = std::tuple<std::string, T_ASC_SC_ROLE, std::vector<std::string>>;

    void connect(Scu& scu, const std::vector<std::pair<const char*, T_ASC_SC_ROLE>>& contexts,
                 const std::vector<std::string>& syntaxes) {
        std::vector<Context> all;
        for (const auto& [sop, role] : contexts) all.emplace_back(sop, role, syntaxes);
        connectWith(scu, all);
    }

    // Configures, optionally secures, and negotiates one association.
    void connectWith(Scu& scu, const std::vector<Context>& contexts) {
        DcmtkSetup::ensure();
        scu.setAETitle(local.aeTitle.c_str());
        scu.setPeerHostName(remote.host.c_str());
        scu.setPeerPort(remote.port);
        scu.setPeerAETitle(remote.aeTitle.c_str());
        const Uint32 t = Uint32(std::max(1, local.timeoutSeconds));
        scu.setACSETimeout(t);
        scu.setDIMSETimeout(t);
        scu.setDIMSEBlockingMode(DIMSE_NONBLOCKING);
        scu.setConnectionTimeout(Sint32(t));
        scu.setMaxReceivePDULength(remote.maxPdu);
        for (const auto& [sop, role, syntaxList] : contexts) {
            OFList<OFString> syntaxes;
            for (const auto& ts : syntaxList) syntaxes.push_back(ts.c_str());
            scu.addPresentationContext(sop.c_str(), syntaxes, role);
        }
        OFCondition c = scu.initNetwork();
        if (c.bad()) throw core::Error(where() + ": cannot start networking (" + std::string(c.text()) + ")");
        if (remote.tls)
            secure(scu);
        else if (OFCondition q = scu.secureWith(quickAck.get()); q.bad())  // DcmSCU's one way to set a transport layer
            throw core::Error(where() + ": cannot set up the connection (" + std::string(q.text()) + ")");
        c = scu.negotiateAssociation();
        if (c.bad() && remote.tls &&
            (lastVerifyError == X509_V_ERR_HOSTNAME_MISMATCH || lastVerifyError == X509_V_ERR_IP_ADDRESS_MISMATCH))
            throw core::Error(where() + ": its TLS certificate does not name " + remote.host +
                              " (it was issued for another host); connect by a name the certificate holds, or ask "
                              "for a certificate that names this one");
        if (c.bad() && remote.tls && lastVerifyError != X509_V_OK)
            throw core::Error(where() + ": its TLS certificate was refused (" +
                              X509_verify_cert_error_string(lastVerifyError) + ")");
        if (c == DUL_ASSOCIATIONREJECTED)
            throw AssociationRejected(PacsProtocol::describeAssociationFailure(where(), c.text(), local.aeTitle,
                                                                               remote.aeTitle, local.timeoutSeconds));
        if (c.bad()) throw core::Error(PacsProtocol::describeAssociationFailure(where(), c.text(), local.aeTitle,
                                                                               remote.aeTitle, local.timeoutSeconds));
    }

    /// Sends instances over one association; onEach after each.
    std::size_t storeOn(const std::vector<DicomInstance>& headers, const std::function<void()>& onEach);

    T_ASC_PresentationContextID context(Scu& scu, const char* sop, const char* what) {
        const T_ASC_PresentationContextID id = scu.findPresentationContextID(sop, "");
        if (id == 0) {
            scu.releaseAssociation();
            throw core::Error(where() + " does not offer " + what + " (no accepted presentation context)");
        }
        return id;
    }
};

PacsClient::PacsClient(LocalNode local, PacsNode remote) : impl_(std::make_unique<Impl>()) {
    impl_->local = std::move(local);
    impl_->remote = std::move(remote);
    if (impl_->remote.kind == NodeKind::DicomWeb)
        impl_->web = std::make_unique<DicomWebClient>(impl_->local, impl_->remote);
}
PacsClient::~PacsClient() = default;

void PacsClient::cancelWith(const core::JobContext& job) {
    impl_->job = &job;
    if (impl_->web) impl_->web->cancelWith(job);
}

void PacsClient::echo() {
    if (impl_->web) return impl_->web->echo();
    Scu scu;
    impl_->connect(scu, {{UID_VerificationSOPClass, ASC_SC_ROLE_DEFAULT}}, PacsProtocol::basicSyntaxes());
    const OFCondition c = scu.sendECHORequest(impl_->context(scu, UID_VerificationSOPClass, "verification (C-ECHO)"));
    scu.releaseAssociation();
    if (c.bad()) throw core::Error(impl_->where() + ": C-ECHO failed (" + std::string(c.text()) + ")");
}

std::size_t PacsClient::find(QueryLevel level, const QueryKeys& keys,
                             const std::function<bool(const QueryResult&)>& onResult) {
    if (impl_->web) return impl_->web->find(level, keys, onResult);
    Scu scu;
    scu.level = level;
    scu.onFind = onResult;
    impl_->connect(scu, {{UID_FINDStudyRootQueryRetrieveInformationModel, ASC_SC_ROLE_DEFAULT}},
                   PacsProtocol::basicSyntaxes());
    DcmDataset query;
    PacsProtocol::fillQuery(query, level, keys);
    const OFCondition c = scu.sendFINDRequest(
        impl_->context(scu, UID_FINDStudyRootQueryRetrieveInformationModel, "Study Root query (C-FIND)"), &query,
        nullptr);
    if (c.bad()) {
        scu.abortAssociation();
        throw core::Error(PacsProtocol::describeDimseFailure(impl_->where(), "C-FIND", c.text(), impl_->local.timeoutSeconds));
    }
    scu.releaseAssociation();
    if (!scu.cancelled) PacsProtocol::checkFinalStatus(impl_->where(), "query", scu.finalStatus, impl_->local.aeTitle);
    return scu.delivered;
}

RetrieveProgress PacsClient::get(const std::string& studyUid, const std::string& seriesUid,
                                 const std::string& storageDir,
                                 const std::function<void(const DicomInstance&)>& onStored,
                                 const std::function<void(const RetrieveProgress&)>& onProgress,
                                 const std::vector<std::string>& sopUids) {
    if (impl_->web) return impl_->web->get(studyUid, seriesUid, storageDir, onStored, onProgress, sopUids);
    IncomingStore store(storageDir, impl_->local.minFreeBytes);
    IncomingFiler filer(store);
    Scu scu;
    scu.job = impl_->job;
    scu.store = &store;
    scu.filer = &filer;
    scu.onStored = onStored;
    scu.onProgress = onProgress;
    scu.setStorageMode(DCMSCU_STORAGE_BIT_PRESERVING);
    scu.setStorageDir(storageDir.c_str());
    std::vector<std::pair<const char*, T_ASC_SC_ROLE>> contexts{
        {UID_GETStudyRootQueryRetrieveInformationModel, ASC_SC_ROLE_DEFAULT}};
    for (const char* sop : PacsProtocol::storageClasses()) contexts.push_back({sop, ASC_SC_ROLE_SCP});
    impl_->connect(scu, contexts, PacsProtocol::storageSyntaxes());
    DcmDataset keys;
    PacsProtocol::fillRetrieve(keys, studyUid, seriesUid, sopUids);
    const OFCondition c = scu.sendCGETRequest(
        impl_->context(scu, UID_GETStudyRootQueryRetrieveInformationModel, "retrieve by C-GET"), &keys, nullptr);
    if (c.bad()) {
        scu.abortAssociation();
        filer.finishAfterFailure([&scu](const DicomInstance& in) { scu.stored(in); });
        if (scu.jobCancelled()) throw core::Cancelled();
        std::string why = PacsProtocol::describeDimseFailure(impl_->where(), "C-GET", c.text(), impl_->local.timeoutSeconds);
        if (!scu.storeError.empty()) why += "; " + scu.storeError;
        throw core::Error(why + " (" + std::to_string(scu.progress.received) + " instances were stored completely)");
    }
    scu.releaseAssociation();
    try {  // the last instances are flushed and reported before the retrieve is done
        filer.finish([&scu](const DicomInstance& in) { scu.stored(in); });
    } catch (const core::Error& e) {
        if (scu.jobCancelled()) throw core::Cancelled();
        throw core::Error(impl_->where() + " (C-GET): " + e.what() + " (" + std::to_string(scu.progress.received) +
                          " instances were stored completely)");
    }
    if (scu.jobCancelled()) throw core::Cancelled();
    PacsProtocol::checkFinalStatus(impl_->where(), "C-GET", scu.finalStatus, impl_->local.aeTitle);
    return scu.progress;
}

RetrieveProgress PacsClient::move(const std::string& studyUid, const std::string& seriesUid,
                                  const std::string& destinationAe,
                                  const std::function<void(const RetrieveProgress&)>& onProgress,
                                  const std::vector<std::string>& sopUids) {
    if (impl_->web)
        throw core::Error("DICOMweb node '" + impl_->remote.name + "' retrieves by WADO-RS, not C-MOVE; use get");
    Scu scu;
    scu.job = impl_->job;
    scu.onProgress = onProgress;
    impl_->connect(scu, {{UID_MOVEStudyRootQueryRetrieveInformationModel, ASC_SC_ROLE_DEFAULT}},
                   PacsProtocol::basicSyntaxes());
    DcmDataset keys;
    PacsProtocol::fillRetrieve(keys, studyUid, seriesUid, sopUids);
    const OFCondition c = scu.sendMOVERequest(
        impl_->context(scu, UID_MOVEStudyRootQueryRetrieveInformationModel, "retrieve by C-MOVE"),
        destinationAe.c_str(), &keys, nullptr);
    if (c.bad()) {
        scu.abortAssociation();
        if (scu.jobCancelled()) throw core::Cancelled();
        throw core::Error(PacsProtocol::describeDimseFailure(impl_->where(), "C-MOVE", c.text(), impl_->local.timeoutSeconds));
    }
    scu.releaseAssociation();
    if (scu.jobCancelled()) throw core::Cancelled();
    PacsProtocol::checkFinalStatus(impl_->where(), "C-MOVE to '" + destinationAe + "'", scu.finalStatus, destinationAe);
    return scu.progress;
}

std::size_t PacsClient::Impl::storeOn(const std::vector<DicomInstance>& headers, const std::function<void()>& onEach) {
    // One presentation context per SOP class present, offering the file's own transfer syntax
    // (so nothing is re-encoded) and explicit little endian.
    std::set<std::pair<std::string, std::string>> contexts;
    for (const auto& in : headers) contexts.insert({in.sopClassUid, in.transferSyntaxUid});
    Scu scu;
    std::vector<Impl::Context> negotiated;
    for (const auto& [sop, ts] : contexts) {
        std::vector<std::string> syntaxes{ts};
        if (ts != UID_LittleEndianExplicitTransferSyntax) syntaxes.push_back(UID_LittleEndianExplicitTransferSyntax);
        negotiated.emplace_back(sop, ASC_SC_ROLE_DEFAULT, syntaxes);
    }
    connectWith(scu, negotiated);
    std::size_t accepted = 0;
    for (const auto& in : headers) {
        if (job && job->cancelled()) {
            scu.abortAssociation();
            throw core::Cancelled();
        }
        const T_ASC_PresentationContextID id =
            scu.findPresentationContextID(in.sopClassUid.c_str(), in.transferSyntaxUid.c_str());
        Uint16 status = 0;
        const OFCondition c = scu.sendSTORERequest(id, in.path.c_str(), nullptr, status);
        if (c.bad()) {
            scu.abortAssociation();
            throw core::Error(
                PacsProtocol::describeDimseFailure(where(), "C-STORE of " + in.path, c.text(), local.timeoutSeconds));
        }
        if (status == 0x0000 || (status & 0xF000) == 0xB000) ++accepted;
        if (onEach) onEach();
    }
    scu.releaseAssociation();
    return accepted;
}

std::size_t PacsClient::store(const std::vector<std::string>& files, const std::function<void(std::size_t)>& onProgress) {
    if (impl_->web) return impl_->web->store(files, onProgress);
    std::vector<DicomInstance> headers;
    for (const auto& f : files) {
        DicomInstance in;
        if (DicomHeaderReader::read(f, in) != DicomHeaderReader::Kind::Dicom) throw core::Error(f + ": not a DICOM file");
        headers.push_back(std::move(in));
    }
    std::vector<std::vector<DicomInstance>> chunks;
    for (std::size_t at = 0; at < headers.size(); at += kFilesPerAssociation)
        chunks.emplace_back(headers.begin() + long(at),
                            headers.begin() + long(std::min(headers.size(), at + kFilesPerAssociation)));
    std::mutex mutex;
    std::size_t sent = 0;
    auto onEach = [&] {
        std::lock_guard lock(mutex);
        ++sent;
        if (onProgress) onProgress(sent);
    };
    const int workers = std::min<int>(std::max(1, impl_->local.parallelAssociations), int(chunks.size()));
    if (workers <= 1) return chunks.empty() ? 0 : impl_->storeOn(headers, onEach);
    // Several associations at once, each taking the next chunk; a PACS that rejects an extra
    // association is given time, then left to the associations it did accept.
    std::atomic<std::size_t> next{0}, accepted{0};
    std::atomic<int> working{0};
    std::exception_ptr failure;
    auto work = [&] {
        PacsClient own(impl_->local, impl_->remote);
        if (impl_->job) own.cancelWith(*impl_->job);
        try {
            for (std::size_t i = next++; i < chunks.size(); i = next++) {
                for (int attempt = 0;; ++attempt) {
                    try {
                        accepted += own.impl_->storeOn(chunks[i], onEach);
                        ++working;
                        break;
                    } catch (const AssociationRejected&) {
                        if (attempt >= 3 || (working == 0 && attempt >= 2)) throw;
                        std::this_thread::sleep_for(std::chrono::milliseconds(250 << attempt));
                    }
                }
            }
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!failure) failure = std::current_exception();
            next = chunks.size();  // the others stop after their chunk
        }
    };
    std::vector<std::thread> threads;
    for (int w = 0; w < workers; ++w) threads.emplace_back(work);
    for (auto& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
    return accepted;
}

}  // namespace hvx::dicom
