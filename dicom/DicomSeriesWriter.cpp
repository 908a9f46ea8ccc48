#include "dicom/DicomSeriesWriter.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcrleerg.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmjpeg/djencode.h>
#include <dcmtk/dcmjpeg/djrplol.h>
#include <dcmtk/dcmjpls/djencode.h>
#include <dcmtk/dcmjpls/djrparam.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <mutex>

#include "core/base/Error.h"
#include "dicom/DcmtkSetup.h"

namespace hvx::dicom {

namespace {
std::string newUid() {
    char buf[100];
    dcmGenerateUniqueIdentifier(buf, SITE_INSTANCE_UID_ROOT);
    return buf;
}

std::string today() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[16];
    std::strftime(buf, sizeof buf, "%Y%m%d", &tm);
    return buf;
}

std::string decimals(std::initializer_list<double> values) {
    std::string s;
    for (double v : values) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.10g", v);
        if (!s.empty()) s += '\\';
        s += buf;
    }
    return s;
}

E_TransferSyntax syntaxOf(const std::string& name, DcmRepresentationParameter*& param) {
    static DJ_RPLossless jpegLossless(1, 0);
    static DJLSRepresentationParameter jpegLs(0, OFTrue);
    param = nullptr;
    if (name == "explicit-little") return EXS_LittleEndianExplicit;
    if (name == "implicit-little") return EXS_LittleEndianImplicit;
    if (name == "explicit-big") return EXS_BigEndianExplicit;
    if (name == "deflate") return EXS_DeflatedLittleEndianExplicit;
    if (name == "rle") return EXS_RLELossless;
    if (name == "jpeg-lossless") {
        param = &jpegLossless;
        return EXS_JPEGProcess14SV1;
    }
    if (name == "jpeg-ls") {
        param = &jpegLs;
        return EXS_JPEGLSLossless;
    }
    throw core::Error("unsupported transfer syntax '" + name +
                      "' (explicit-little, implicit-little, explicit-big, deflate, rle, jpeg-lossless, jpeg-ls)");
}

void registerEncoders() {
    static std::once_flag once;
    std::call_once(once, [] {
        DJEncoderRegistration::registerCodecs();
        // Raw, not DCMTK's default "cooked" mode: on incompressible 16-bit data (full-range signed
        // noise) the cooked encoder of DCMTK 3.6.7 overran its buffer (double free, or slices
        // CharLS could not decode); `dcmcjpls +pc` does the same, `+pr` does not.
        DJLSEncoderRegistration::registerCodecs(0, 0, 0, 0, OFFalse);
        DcmRLEEncoderRegistration::registerCodecs();
    });
}

void putCommon(DcmItem* ds, const DicomWriteOptions& o, const core::VolumeGeometry& g, const std::string& modality,
               const std::string& studyUid, const std::string& seriesUid, const std::string& frameOfReference,
               bool eightBit) {
    // Names and descriptions are UTF-8 here (the study database, the command line): said so.
    // Declared Latin-1, a "Müller" had been read back by every other tool as "MÃ¼ller".
    ds->putAndInsertString(DCM_SpecificCharacterSet, "ISO_IR 192");
    ds->putAndInsertString(DCM_PatientName, o.patientName.c_str());
    ds->putAndInsertString(DCM_PatientID, o.patientId.c_str());
    ds->putAndInsertString(DCM_PatientBirthDate, o.patientBirthDate.c_str());
    ds->putAndInsertString(DCM_PatientSex, o.patientSex.c_str());
    const std::string date = o.studyDate.empty() ? today() : o.studyDate;
    ds->putAndInsertString(DCM_StudyDate, date.c_str());
    ds->putAndInsertString(DCM_StudyTime, "120000");
    ds->putAndInsertString(DCM_SeriesDate, date.c_str());
    ds->putAndInsertString(DCM_AccessionNumber, o.accessionNumber.c_str());
    ds->putAndInsertString(DCM_ReferringPhysicianName, "");
    ds->putAndInsertString(DCM_StudyID, "1");
    ds->putAndInsertString(DCM_StudyDescription, o.studyDescription.c_str());
    ds->putAndInsertString(DCM_SeriesDescription, o.seriesDescription.c_str());
    ds->putAndInsertString(DCM_Modality, modality.c_str());
    ds->putAndInsertString(DCM_Manufacturer, "Holovox");
    ds->putAndInsertString(DCM_StudyInstanceUID, studyUid.c_str());
    ds->putAndInsertString(DCM_SeriesInstanceUID, seriesUid.c_str());
    ds->putAndInsertString(DCM_FrameOfReferenceUID, frameOfReference.c_str());
    ds->putAndInsertString(DCM_PositionReferenceIndicator, "");
    // Type 2 and 2C attributes of General Series and Patient: present, empty where unknown.
    ds->putAndInsertString(DCM_Laterality, "");
    ds->putAndInsertString(DCM_PatientPosition, "");
    ds->putAndInsertString(DCM_SeriesNumber, std::to_string(o.seriesNumber).c_str());
    ds->putAndInsertUint16(DCM_SamplesPerPixel, 1);
    ds->putAndInsertString(DCM_PhotometricInterpretation, g.monochrome1 ? "MONOCHROME1" : "MONOCHROME2");
    ds->putAndInsertUint16(DCM_Rows, Uint16(g.dims[1]));
    ds->putAndInsertUint16(DCM_Columns, Uint16(g.dims[0]));
    if (!o.derivation.empty()) {  // ST of at most 1024 characters, cut at a character's start
        std::size_t end = std::min<std::size_t>(o.derivation.size(), 1024);
        while (end > 0 && end < o.derivation.size() && (static_cast<unsigned char>(o.derivation[end]) & 0xC0) == 0x80) --end;
        ds->putAndInsertString(DCM_DerivationDescription, o.derivation.substr(0, end).c_str());
    }
    const Uint16 bits = eightBit ? 8 : 16;
    ds->putAndInsertUint16(DCM_BitsAllocated, bits);
    ds->putAndInsertUint16(DCM_BitsStored, bits);
    ds->putAndInsertUint16(DCM_HighBit, Uint16(bits - 1));
    ds->putAndInsertUint16(DCM_PixelRepresentation, g.scalarType == core::ScalarType::Int16 ? 1 : 0);
}

/// The SOP class an export uses for a modality: CT and MR images as such, anything else (PET,
/// NM, a NIfTI of unknown origin...) as Secondary Capture, which claims no acquisition.
const char* sopClassFor(const std::string& modality) {
    if (modality == "CT") return UID_CTImageStorage;
    if (modality == "MR") return UID_MRImageStorage;
    return UID_SecondaryCaptureImageStorage;
}

/// PatientOrientation letters of a direction: the patient axes it runs along, largest first
/// (L/R, P/A, H/F), as Secondary Capture images state their orientation.
std::string orientationLetters(const glm::dvec3& d) {
    std::vector<std::pair<double, char>> parts = {{std::abs(d.x), d.x > 0 ? 'L' : 'R'},
                                                  {std::abs(d.y), d.y > 0 ? 'P' : 'A'},
                                                  {std::abs(d.z), d.z > 0 ? 'H' : 'F'}};
    std::sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::string out;
    for (const auto& [size, letter] : parts)
        if (size > 0.25) out += letter;
    return out;
}

/// What the single-frame IODs require beyond the common modules: the CT and MR Image modules'
/// Type 1 and 2 attributes (empty where the acquisition is unknown), or SC Equipment.
void putModalityModule(DcmItem* ds, const std::string& modality, const core::VolumeGeometry& g) {
    if (modality == "CT") {
        ds->putAndInsertString(DCM_KVP, "");
        ds->putAndInsertString(DCM_AcquisitionNumber, "");
    } else if (modality == "MR") {
        ds->putAndInsertString(DCM_ScanningSequence, "RM");  // research mode: the sequence is not known
        ds->putAndInsertString(DCM_SequenceVariant, "NONE");
        ds->putAndInsertString(DCM_ScanOptions, "");
        ds->putAndInsertString(DCM_MRAcquisitionType, "");
        ds->putAndInsertString(DCM_RepetitionTime, "");
        ds->putAndInsertString(DCM_EchoTime, "");
        ds->putAndInsertString(DCM_EchoTrainLength, "");
        ds->putAndInsertString(DCM_AcquisitionNumber, "");
    } else {
        ds->putAndInsertString(DCM_ConversionType, "WSD");  // workstation
        ds->putAndInsertString(DCM_PatientOrientation,
                               (orientationLetters(g.direction[0]) + "\\" + orientationLetters(g.direction[1])).c_str());
    }
}

void putPlane(DcmItem* item, const core::VolumeGeometry& g, std::uint32_t k, bool position, bool orientation,
              bool spacing, bool rescale, const std::string& modality) {
    if (position) {
        const glm::dvec3 p = g.origin + g.direction[2] * (g.spacing.z * k);
        item->putAndInsertString(DCM_ImagePositionPatient, decimals({p.x, p.y, p.z}).c_str());
    }
    if (orientation) {
        const glm::dvec3 r = g.direction[0], c = g.direction[1];
        item->putAndInsertString(DCM_ImageOrientationPatient, decimals({r.x, r.y, r.z, c.x, c.y, c.z}).c_str());
    }
    if (spacing) {
        item->putAndInsertString(DCM_PixelSpacing, decimals({g.spacing.y, g.spacing.x}).c_str());
        const glm::dvec3 n = glm::normalize(glm::cross(g.direction[0], g.direction[1]));
        item->putAndInsertString(DCM_SliceThickness,
                                 decimals({std::abs(glm::dot(g.direction[2], n)) * g.spacing.z}).c_str());
    }
    if (rescale) {
        item->putAndInsertString(DCM_RescaleIntercept, decimals({g.rescaleIntercept}).c_str());
        item->putAndInsertString(DCM_RescaleSlope, decimals({g.rescaleSlope}).c_str());
        // A CT's values are HU unless its source said otherwise (an iodine map): then unspecified.
        item->putAndInsertString(DCM_RescaleType, modality == "CT" && !g.notHounsfield ? "HU" : "US");
    }
}

void save(DcmFileFormat& file, const std::string& path, E_TransferSyntax xfer, DcmRepresentationParameter* param) {
    DcmDataset* ds = file.getDataset();
    if (param || xfer == EXS_RLELossless) {
        const OFCondition c = ds->chooseRepresentation(xfer, param);
        if (c.bad() || !ds->canWriteXfer(xfer)) throw core::Error(path + ": cannot encode pixel data (" + c.text() + ")");
    }
    const std::string tmp = path + ".partial";
    const OFCondition st = file.saveFile(tmp.c_str(), xfer);
    if (st.bad()) {
        std::remove(tmp.c_str());
        throw core::Error(path + ": cannot write (" + st.text() + ")");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw core::Error(path + ": cannot rename into place");
    }
}

/// `bytes` holds the volume's own type: 8-bit values are written as 8 bits, or widened to 16
/// where `eightBit` is false (CT and MR), 16-bit ones as they are.
void putPixels(DcmItem* ds, const std::vector<std::uint8_t>& bytes, bool eightBit, bool sourceEightBit) {
    if (eightBit) {
        ds->putAndInsertUint8Array(DCM_PixelData, bytes.data(), static_cast<unsigned long>(bytes.size()));
    } else if (sourceEightBit) {
        const std::vector<Uint16> wide(bytes.begin(), bytes.end());
        ds->putAndInsertUint16Array(DCM_PixelData, wide.data(), static_cast<unsigned long>(wide.size()));
    } else {
        ds->putAndInsertUint16Array(DCM_PixelData, reinterpret_cast<const Uint16*>(bytes.data()),
                                    static_cast<unsigned long>(bytes.size() / 2));
    }
}

/// CT and MR images hold 16 bits (PS3.3 C.8.2.1, C.8.3.1); other IODs may hold 8.
bool writesEightBit(const core::VolumeGeometry& g, const std::string& modality) {
    return g.scalarType == core::ScalarType::UInt8 && modality != "CT" && modality != "MR";
}

struct SeriesUids {
    std::string study, series, frameOfReference;
};

/// One multi-frame object of the Legacy Converted Enhanced CT or MR Image IOD (PS3.3 A.70,
/// A.71): the enhanced IOD for images that did not come from an enhanced acquisition, so it
/// claims no acquisition details Holovox does not know (the Enhanced CT/MR IODs require exposure,
/// coil, echo and timing macros). Geometry and rescale are shared; each frame has its position
/// and its place in the one stack (Frame Content, indexed by In-Stack Position).
void writeLegacyConvertedEnhanced(core::VoxelSource& source, const std::string& path, const DicomWriteOptions& o,
                                  const std::string& modality, const SeriesUids& uids, E_TransferSyntax xfer,
                                  DcmRepresentationParameter* param, core::JobContext& job) {
    const core::VolumeGeometry& g = source.geometry();
    const bool ct = modality == "CT";
    DcmFileFormat file;
    DcmDataset* ds = file.getDataset();
    const char* sop = ct ? UID_LegacyConvertedEnhancedCTImageStorage : UID_LegacyConvertedEnhancedMRImageStorage;
    ds->putAndInsertString(DCM_SOPClassUID, sop);
    ds->putAndInsertString(DCM_SOPInstanceUID, newUid().c_str());
    const char* type = "DERIVED\\PRIMARY\\VOLUME\\NONE";  // value 2 is PRIMARY in the enhanced IODs
    ds->putAndInsertString(DCM_ImageType, type);
    putCommon(ds, o, g, modality, uids.study, uids.series, uids.frameOfReference, writesEightBit(g, modality));
    ds->putAndInsertString(DCM_InstanceNumber, "1");
    ds->putAndInsertString(DCM_ContentDate, (o.studyDate.empty() ? today() : o.studyDate).c_str());
    ds->putAndInsertString(DCM_ContentTime, "120000");
    // Enhanced General Equipment: Type 1.
    ds->putAndInsertString(DCM_ManufacturerModelName, "Holovox");
    ds->putAndInsertString(DCM_DeviceSerialNumber, "0");
    ds->putAndInsertString(DCM_SoftwareVersions, "Holovox");
    // Common CT/MR image description, image level; the same per frame below.
    auto describe = [](DcmItem* item) {
        item->putAndInsertString(DCM_PixelPresentation, "MONOCHROME");
        item->putAndInsertString(DCM_VolumetricProperties, "VOLUME");
        item->putAndInsertString(DCM_VolumeBasedCalculationTechnique, "NONE");
    };
    describe(ds);
    ds->putAndInsertString(DCM_PresentationLUTShape, "IDENTITY");
    ds->putAndInsertString(DCM_BurnedInAnnotation, "NO");
    ds->putAndInsertString(DCM_LossyImageCompression, "00");
    ds->putAndInsertString(DCM_ContentQualification, "RESEARCH");
    ds->insertEmptyElement(DCM_AcquisitionContextSequence);
    ds->putAndInsertString(DCM_NumberOfFrames, std::to_string(g.dims[2]).c_str());
    // Multi-frame Dimension: one stack, frames indexed by their In-Stack Position Number.
    const std::string dimensionUid = newUid();
    DcmItem* it = nullptr;
    ds->findOrCreateSequenceItem(DCM_DimensionOrganizationSequence, it, 0);
    it->putAndInsertString(DCM_DimensionOrganizationUID, dimensionUid.c_str());
    ds->putAndInsertString(DCM_DimensionOrganizationType, "3D");
    ds->findOrCreateSequenceItem(DCM_DimensionIndexSequence, it, 0);
    it->putAndInsertString(DCM_DimensionOrganizationUID, dimensionUid.c_str());
    it->putAndInsertTagKey(DCM_DimensionIndexPointer, DCM_InStackPositionNumber);
    it->putAndInsertTagKey(DCM_FunctionalGroupPointer, DCM_FrameContentSequence);

    DcmItem* shared = nullptr;
    ds->findOrCreateSequenceItem(DCM_SharedFunctionalGroupsSequence, shared, 0);
    shared->findOrCreateSequenceItem(DCM_PixelMeasuresSequence, it, 0);
    putPlane(it, g, 0, false, false, true, false, modality);
    shared->findOrCreateSequenceItem(DCM_PlaneOrientationSequence, it, 0);
    putPlane(it, g, 0, false, true, false, false, modality);
    shared->findOrCreateSequenceItem(DCM_PixelValueTransformationSequence, it, 0);
    putPlane(it, g, 0, false, false, false, true, modality);
    shared->findOrCreateSequenceItem(ct ? DCM_CTImageFrameTypeSequence : DCM_MRImageFrameTypeSequence, it, 0);
    it->putAndInsertString(DCM_FrameType, type);
    describe(it);

    const std::size_t sliceBytes = std::size_t(g.dims[0]) * g.dims[1] * core::scalarSize(g.scalarType);
    std::vector<std::uint8_t> all(sliceBytes * g.dims[2]);
    for (std::uint32_t k = 0; k < g.dims[2]; ++k) {
        job.throwIfCancelled();
        DcmItem* frame = nullptr;
        ds->findOrCreateSequenceItem(DCM_PerFrameFunctionalGroupsSequence, frame, long(k));
        frame->findOrCreateSequenceItem(DCM_PlanePositionSequence, it, 0);
        putPlane(it, g, k, true, false, false, false, modality);
        frame->findOrCreateSequenceItem(DCM_FrameContentSequence, it, 0);
        it->putAndInsertUint32(DCM_DimensionIndexValues, k + 1);
        it->putAndInsertString(DCM_StackID, "1");
        it->putAndInsertUint32(DCM_InStackPositionNumber, k + 1);
        frame->findOrCreateSequenceItem(DCM_UnassignedPerFrameConvertedAttributesSequence, it, 0);  // one empty item
        source.readSlices(k, 1, all.data() + k * sliceBytes);
        job.report(double(k + 1) / g.dims[2], "writing frames");
    }
    putPixels(ds, all, writesEightBit(g, modality), g.scalarType == core::ScalarType::UInt8);
    save(file, path, xfer, param);
}
}  // namespace

std::vector<std::string> DicomSeriesWriter::write(core::VoxelSource& source, const std::string& folder,
                                                  const DicomWriteOptions& o, core::JobContext& job) {
    DcmtkSetup::ensure();
    registerEncoders();
    const core::VolumeGeometry& g = source.geometry();
    if (g.scalarType == core::ScalarType::Float32)
        throw core::Error(source.describe() + ": float volumes are exported through FloatToInt16Source (holovox-cli "
                                              "export-dicom does it), not directly");
    if (g.dims[0] > 65535 || g.dims[1] > 65535) throw core::Error(source.describe() + ": slices too large for DICOM");
    // An export would state an assumption as a fact that the next reader cannot question.
    if (g.spacingAssumed || g.orientationAssumed)
        throw core::Error(source.describe() + ": the source gave no " +
                          (g.spacingAssumed ? std::string("pixel spacing") : std::string("orientation")) +
                          " (Holovox assumed one to show it); an export would write the assumption as a fact");
    // ImageOrientationPatient states two perpendicular unit vectors: a grid sheared within its
    // slices has no DICOM form (one sheared along k is a tilted gantry, written as such).
    if (std::abs(glm::dot(glm::normalize(g.direction[0]), glm::normalize(g.direction[1]))) > 1e-4)
        throw core::Error(source.describe() + ": its rows and columns are not perpendicular (the grid is sheared "
                                              "within its slices), which DICOM's Image Orientation cannot state");
    DcmRepresentationParameter* param = nullptr;
    const E_TransferSyntax xfer = syntaxOf(o.transferSyntax, param);
    std::filesystem::path target = std::filesystem::path(folder).lexically_normal();
    if (target.filename().empty()) target = target.parent_path();  // "out/" is "out"
    std::error_code linkError;
    if (std::filesystem::is_symlink(target, linkError)) target = std::filesystem::canonical(target, linkError);  // where it points
    std::error_code ec;
    if (std::filesystem::exists(target, ec) &&
        (!std::filesystem::is_directory(target, ec) || !std::filesystem::is_empty(target, ec)))
        throw core::Error(folder + ": " + (std::filesystem::is_directory(target, ec) ? "already holds files" : "is a file") +
                          "; an export goes into a new or empty folder, so that it never mixes with or replaces "
                          "other files");
    // A new folder is written beside the target and renamed to it when whole; an empty one (a
    // mount point, ".") is written into, and what was written is removed on failure. Either
    // way a failed or cancelled export leaves nothing behind.
    const bool intoEmpty = std::filesystem::exists(target, ec);
    const std::string unique = newUid();
    const std::filesystem::path staging =
        intoEmpty ? target : std::filesystem::path(target.string() + ".partial-" + unique.substr(unique.size() - 8));
    if (!intoEmpty) {
        if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path(), ec);
        if (ec || !std::filesystem::create_directory(staging, ec))  // a new folder, never one already there
            throw core::Error(folder + ": cannot create folder (" + (ec ? ec.message() : std::string("it exists")) + ")");
    }
    std::vector<std::string> names;  // the files written, in slice order
    auto discard = [&] {
        std::error_code ignored;
        if (!intoEmpty) std::filesystem::remove_all(staging, ignored);
        else
            for (const auto& n : names) std::filesystem::remove(staging / n, ignored);
    };
    const std::string modality = o.modality.empty() ? (g.modality.empty() ? std::string("OT") : g.modality) : o.modality;
    if (o.enhancedMultiframe && modality != "CT" && modality != "MR") {
        discard();
        throw core::Error("an enhanced multi-frame export is Legacy Converted Enhanced CT or MR; " + modality +
                          " is written as single-frame images (leave out --enhanced)");
    }
    const std::string studyUid = o.studyUid.empty() ? newUid() : o.studyUid;
    const std::string seriesUid = o.seriesUid.empty() ? newUid() : o.seriesUid;
    // Kept from a DICOM source, so the export registers with it; new otherwise.
    const std::string frameOfReference = o.frameOfReferenceUid.empty() ? newUid() : o.frameOfReferenceUid;
    const std::size_t sliceBytes = std::size_t(g.dims[0]) * g.dims[1] * core::scalarSize(g.scalarType);
    const bool eightBit = writesEightBit(g, modality), sourceEightBit = g.scalarType == core::ScalarType::UInt8;
    try {
        if (o.enhancedMultiframe) {
            writeLegacyConvertedEnhanced(source, (staging / "ENHANCED.dcm").string(), o, modality,
                                         {studyUid, seriesUid, frameOfReference}, xfer, param, job);
            names.push_back("ENHANCED.dcm");
        } else {
            std::vector<std::uint8_t> slice(sliceBytes);
            for (std::uint32_t k = 0; k < g.dims[2]; ++k) {
                job.throwIfCancelled();
                DcmFileFormat file;
                DcmDataset* ds = file.getDataset();
                const std::string sopUid = newUid();
                ds->putAndInsertString(DCM_SOPClassUID, sopClassFor(modality));
                ds->putAndInsertString(DCM_SOPInstanceUID, sopUid.c_str());
                ds->putAndInsertString(DCM_ImageType, "DERIVED\\SECONDARY\\AXIAL");
                putCommon(ds, o, g, modality, studyUid, seriesUid, frameOfReference, eightBit);
                ds->putAndInsertString(DCM_InstanceNumber, std::to_string(k + 1).c_str());
                putPlane(ds, g, k, true, true, true, true, modality);
                putModalityModule(ds, modality, g);
                source.readSlices(k, 1, slice.data());
                putPixels(ds, slice, eightBit, sourceEightBit);
                char name[32];
                std::snprintf(name, sizeof name, "IMG%05u.dcm", k + 1);
                save(file, (staging / name).string(), xfer, param);
                names.push_back(name);
                job.report(double(k + 1) / g.dims[2], "writing slices");
            }
        }
        if (!intoEmpty) {
            std::filesystem::rename(staging, target, ec);
            if (ec) throw core::Error(folder + ": cannot move the written series into place (" + ec.message() + ")");
        }
    } catch (...) {
        discard();
        throw;
    }
    std::vector<std::string> paths;
    for (const auto& n : names) paths.push_back((target / n).string());
    return paths;
}

}  // namespace hvx::dicom
