#include "dicom/DicomFileProbe.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcuid.h>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"

namespace hvx::dicom {

DicomFileProbe DicomFileProbe::probe(const std::string& path) {
    DicomInstance in;
    if (DicomHeaderReader::read(path, in) != DicomHeaderReader::Kind::Dicom)
        throw core::Error(path + ": not a readable DICOM file");
    DicomFileProbe p;
    p.path = path;
    p.sopClassUid = in.sopClassUid;
    if (p.sopClassUid.empty()) throw core::Error(path + ": DICOM file has no SOP Class UID");
    p.transferSyntaxUid = in.transferSyntaxUid;
    p.modality = in.modality;
    p.patientName = in.patientName;
    p.patientId = in.patientId;
    p.studyInstanceUid = in.studyInstanceUid;
    p.seriesInstanceUid = in.seriesInstanceUid;
    p.rows = in.rows;
    p.columns = in.columns;
    p.frames = in.frames;
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
