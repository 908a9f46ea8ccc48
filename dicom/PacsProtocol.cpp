#include "dicom/PacsProtocol.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdatset.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcuid.h>

#include <algorithm>
#include <cstdio>

#include "core/base/Error.h"

namespace hvx::dicom {

namespace {
bool has(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }
std::string hex(std::uint16_t v) {
    char b[8];
    std::snprintf(b, sizeof b, "0x%04X", v);
    return b;
}
}  // namespace

std::vector<std::string> PacsProtocol::basicSyntaxes() {
    return {UID_LittleEndianExplicitTransferSyntax, UID_LittleEndianImplicitTransferSyntax};
}

std::vector<std::string> PacsProtocol::storageSyntaxes() {
    return {UID_LittleEndianExplicitTransferSyntax, UID_LittleEndianImplicitTransferSyntax,
            UID_DeflatedExplicitVRLittleEndianTransferSyntax, UID_BigEndianExplicitTransferSyntax,
            UID_RLELosslessTransferSyntax, UID_JPEGProcess14SV1TransferSyntax, UID_JPEGProcess14TransferSyntax,
            UID_JPEGProcess1TransferSyntax, UID_JPEGProcess2_4TransferSyntax, UID_JPEGLSLosslessTransferSyntax,
            UID_JPEGLSLossyTransferSyntax, UID_JPEG2000LosslessOnlyTransferSyntax, UID_JPEG2000TransferSyntax};
}

std::vector<const char*> PacsProtocol::storageClasses() {
    return {UID_CTImageStorage, UID_EnhancedCTImageStorage, UID_MRImageStorage, UID_EnhancedMRImageStorage,
            UID_SecondaryCaptureImageStorage, UID_MultiframeGrayscaleWordSecondaryCaptureImageStorage,
            UID_MultiframeGrayscaleByteSecondaryCaptureImageStorage, UID_PositronEmissionTomographyImageStorage,
            UID_NuclearMedicineImageStorage, UID_ComputedRadiographyImageStorage,
            UID_DigitalXRayImageStorageForPresentation, UID_UltrasoundImageStorage, UID_XRayAngiographicImageStorage,
            UID_RTDoseStorage, UID_EnhancedPETImageStorage, UID_LegacyConvertedEnhancedCTImageStorage,
            UID_LegacyConvertedEnhancedMRImageStorage};
}

void PacsProtocol::fillQuery(DcmDataset& q, QueryLevel level, const QueryKeys& k) {
    q.putAndInsertString(DCM_QueryRetrieveLevel,
                         level == QueryLevel::Study ? "STUDY" : level == QueryLevel::Series ? "SERIES" : "IMAGE");
    // Keys are UTF-8: a key beyond ASCII ("Müller*") says so, or the archive would read its
    // bytes as ASCII (PS3.4 C.4.1.1.3.1 matches in the query's character set). An archive
    // answers in a set of its choosing, which toResult reads.
    for (const std::string* key : {&k.patientName, &k.patientId, &k.studyDescription, &k.accessionNumber})
        if (std::any_of(key->begin(), key->end(), [](char c) { return static_cast<unsigned char>(c) >= 0x80; })) {
            q.putAndInsertString(DCM_SpecificCharacterSet, "ISO_IR 192");
            break;
        }
    q.putAndInsertString(DCM_PatientName, k.patientName.c_str());
    q.putAndInsertString(DCM_PatientID, k.patientId.c_str());
    q.putAndInsertString(DCM_PatientBirthDate, "");
    q.putAndInsertString(DCM_StudyInstanceUID, k.studyUid.c_str());
    q.putAndInsertString(DCM_StudyDate, k.studyDate.c_str());
    q.putAndInsertString(DCM_StudyTime, "");
    q.putAndInsertString(DCM_StudyDescription, k.studyDescription.c_str());
    q.putAndInsertString(DCM_AccessionNumber, k.accessionNumber.c_str());
    if (level == QueryLevel::Study) {
        q.putAndInsertString(DCM_ModalitiesInStudy, k.modality.c_str());
        q.putAndInsertString(DCM_NumberOfStudyRelatedInstances, "");
        return;
    }
    q.putAndInsertString(DCM_SeriesInstanceUID, k.seriesUid.c_str());
    q.putAndInsertString(DCM_Modality, k.modality.c_str());
    q.putAndInsertString(DCM_SeriesNumber, "");
    q.putAndInsertString(DCM_SeriesDescription, "");
    if (level == QueryLevel::Series) {
        q.putAndInsertString(DCM_NumberOfSeriesRelatedInstances, "");
        return;
    }
    q.putAndInsertString(DCM_SOPInstanceUID, "");
    q.putAndInsertString(DCM_InstanceNumber, "");
}

void PacsProtocol::fillRetrieve(DcmDataset& k, const std::string& studyUid, const std::string& seriesUid,
                                const std::vector<std::string>& sopUids) {
    k.putAndInsertString(DCM_QueryRetrieveLevel, !sopUids.empty() ? "IMAGE" : seriesUid.empty() ? "STUDY" : "SERIES");
    k.putAndInsertString(DCM_StudyInstanceUID, studyUid.c_str());
    if (!seriesUid.empty()) k.putAndInsertString(DCM_SeriesInstanceUID, seriesUid.c_str());
    std::string list;  // PS3.4 C.2.2.2.2: a list of UIDs, separated by backslashes
    for (const auto& u : sopUids) list += (list.empty() ? "" : "\\") + u;
    if (!list.empty()) k.putAndInsertString(DCM_SOPInstanceUID, list.c_str());
}

std::string PacsProtocol::describeAssociationFailure(const std::string& where, const std::string& reason,
                                                     const std::string& localAe, const std::string& remoteAe,
                                                     int timeoutSeconds) {
    if (has(reason, "Connection refused"))
        return "cannot reach " + where + ": connection refused — is the PACS running, and are host and port right?";
    if (has(reason, "Rejected") || has(reason, "rejected"))
        return where + " rejected the association (" + reason + ") — check that the PACS knows the called AE title '" +
               remoteAe + "' and accepts our AE title '" + localAe + "'";
    if (has(reason, "imeout") || has(reason, "timed out"))
        return where + " did not answer within " + std::to_string(timeoutSeconds) +
               " s — is the host reachable and the port a DICOM port?";
    if (has(reason, "No acceptable") || has(reason, "presentation context"))
        return where + " accepted none of the services Holovox asked for (" + reason + ")";
    if (has(reason, "resolve") || has(reason, "Unknown host") || has(reason, "lookup"))
        return "cannot reach " + where + ": unknown host name";
    return "cannot connect to " + where + ": " + reason;
}

std::string PacsProtocol::describeDimseFailure(const std::string& where, const std::string& operation,
                                               const std::string& reason, int timeoutSeconds) {
    if (has(reason, "imeout") || has(reason, "timed out"))
        return operation + " on " + where + " stalled: no answer within " + std::to_string(timeoutSeconds) + " s";
    return operation + " on " + where + " was interrupted (" + reason + ") — the connection was lost";
}

void PacsProtocol::checkFinalStatus(const std::string& where, const std::string& operation, std::uint16_t status,
                                    const std::string& destinationAe) {
    if (status == 0x0000 || status == 0xFE00) return;  // success, cancelled on request
    if (status == 0xA801)
        throw core::Error(where + " refused the " + operation + ": move destination '" + destinationAe +
                          "' is unknown to it — register that AE title with its host and port on the PACS");
    if ((status & 0xFF00) == 0xA700)
        throw core::Error(where + " refused the " + operation + ": out of resources (status " + hex(status) + ")");
    if (status == 0xB000)
        throw core::Error(operation + " on " + where + " finished with failed sub-operations (status 0xB000): some "
                          "instances did not arrive — retry the retrieve");
    if (status == 0xA900 || (status & 0xF000) == 0xC000) {
        // Some archives (Orthanc) answer an unknown move destination with a plain failure.
        const std::string hint = operation.rfind("C-MOVE", 0) == 0
                                     ? " — check that the move destination '" + destinationAe +
                                           "' is registered on the PACS with Holovox's host and port"
                                     : "";
        throw core::Error(where + " could not process the " + operation + " (status " + hex(status) + ")" + hint);
    }
    if ((status & 0xF000) == 0xA000)
        throw core::Error(where + " refused the " + operation + " (status " + hex(status) + ")");
}

}  // namespace hvx::dicom
