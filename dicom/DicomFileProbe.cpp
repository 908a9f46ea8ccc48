#include "dicom/DicomFileProbe.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcmetinf.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmdata/dcxfer.h>
#include <dcmtk/oflog/oflog.h>

#include "core/Error.h"

namespace hvx::dicom {

namespace {
std::string text(DcmItem* item, const DcmTagKey& key) {
    OFString v;
    if (item && item->findAndGetOFString(key, v).good()) return v.c_str();
    return {};
}
}  // namespace

DicomFileProbe DicomFileProbe::probe(const std::string& path) {
    // Stopping before the pixel data is intended; DCMTK would warn about it on every file.
    static const bool quiet = [] {
        OFLog::configure(OFLogger::OFF_LOG_LEVEL);
        return true;
    }();
    (void)quiet;
    DcmFileFormat file;
    const OFCondition status =
        file.loadFileUntilTag(path.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength, ERM_autoDetect, DCM_PixelData);
    if (status.bad()) throw core::Error(path + ": not a readable DICOM file (" + status.text() + ")");
    DcmDataset* ds = file.getDataset();
    DcmMetaInfo* meta = file.getMetaInfo();
    DicomFileProbe p;
    p.path = path;
    p.sopClassUid = text(ds, DCM_SOPClassUID);
    if (p.sopClassUid.empty()) p.sopClassUid = text(meta, DCM_MediaStorageSOPClassUID);
    if (p.sopClassUid.empty()) throw core::Error(path + ": DICOM file has no SOP Class UID");
    p.transferSyntaxUid = DcmXfer(ds->getOriginalXfer()).getXferID();
    p.modality = text(ds, DCM_Modality);
    p.patientName = text(ds, DCM_PatientName);
    p.patientId = text(ds, DCM_PatientID);
    p.studyInstanceUid = text(ds, DCM_StudyInstanceUID);
    p.seriesInstanceUid = text(ds, DCM_SeriesInstanceUID);
    Uint16 u16 = 0;
    if (ds->findAndGetUint16(DCM_Rows, u16).good()) p.rows = u16;
    if (ds->findAndGetUint16(DCM_Columns, u16).good()) p.columns = u16;
    Sint32 frames = 1;
    if (ds->findAndGetSint32(DCM_NumberOfFrames, frames).bad() || frames < 1) frames = 1;
    p.frames = p.rows ? std::uint32_t(frames) : 0;
    return p;
}

std::string DicomFileProbe::summary() const {
    const char* sop = dcmFindNameOfUID(sopClassUid.c_str(), "unknown SOP class");
    const char* ts = dcmFindNameOfUID(transferSyntaxUid.c_str(), transferSyntaxUid.c_str());
    std::string s = path + ": " + (modality.empty() ? "??" : modality) + " " + sop + ", patient '" + patientName +
                    "' (" + patientId + ")";
    if (rows) s += ", " + std::to_string(columns) + "x" + std::to_string(rows) + "x" + std::to_string(frames);
    return s + ", " + ts;
}

std::string DicomFileProbe::dcmtkVersion() { return OFFIS_DCMTK_VERSION_STRING; }

}  // namespace hvx::dicom
