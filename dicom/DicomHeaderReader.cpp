#include "dicom/DicomHeaderReader.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcmetinf.h>
#include <dcmtk/dcmdata/dcsequen.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmdata/dcxfer.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/base/Error.h"
#include "dicom/DcmtkSetup.h"
#include "dicom/DatasetText.h"

namespace hvx::dicom {

namespace {
std::string text(DcmItem* item, const DcmTagKey& key) {
    OFString v;
    if (item && item->findAndGetOFStringArray(key, v).good()) {
        std::string s = v.c_str();
        while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
        return s;
    }
    return {};
}

/// The image series a segmentation (SEG) or structure set (RTSTRUCT) was drawn on.
std::string referencedSeries(DcmItem* ds, const std::string& sopClass) {
    DcmItem* item = nullptr;
    if (sopClass == UID_SegmentationStorage) {
        if (ds->findAndGetSequenceItem(DCM_ReferencedSeriesSequence, item, 0).good() && item)
            return text(item, DCM_SeriesInstanceUID);
    } else if (sopClass == UID_RTStructureSetStorage) {
        DcmItem *study = nullptr, *series = nullptr;
        if (ds->findAndGetSequenceItem(DCM_ReferencedFrameOfReferenceSequence, item, 0).good() && item &&
            item->findAndGetSequenceItem(DCM_RTReferencedStudySequence, study, 0).good() && study &&
            study->findAndGetSequenceItem(DCM_RTReferencedSeriesSequence, series, 0).good() && series)
            return text(series, DCM_SeriesInstanceUID);
    }
    return {};
}

// A decimal (DS) or integer (IS) string that is not one whole number: DCMTK reads "-100,7" as
// -100 and says nothing, so a decimal comma would move a slice or change a rescale silently.
bool malformedText(DcmItem* item, const DcmTagKey& key, unsigned long pos) {
    DcmElement* e = nullptr;
    if (item->findAndGetElement(key, e).bad() || !e || (e->ident() != EVR_DS && e->ident() != EVR_IS)) return false;
    OFString s;
    if (e->getOFString(s, pos).bad()) return false;
    std::string t(s.c_str());
    t.erase(0, t.find_first_not_of(' '));
    t.erase(t.find_last_not_of(' ') + 1);
    if (t.empty()) return false;
    char* end = nullptr;
    std::strtod(t.c_str(), &end);
    return end != t.c_str() + t.size();
}

// The number at `pos` of a numeric element; false when it is absent. A DS or IS string that is
// not a number throws core::Error naming the element (strict), or counts as absent (a window).
bool number(DcmItem* item, const DcmTagKey& key, double& out, unsigned long pos = 0, bool strict = true) {
    Float64 v = 0;
    if (!item || item->findAndGetFloat64(key, v, pos).bad() || !std::isfinite(v)) return false;
    if (malformedText(item, key, pos)) {
        if (!strict) return false;
        OFString all;
        item->findAndGetOFStringArray(key, all);
        throw core::Error(std::string(DcmTag(key).getTagName()) + " '" + all.c_str() + "' is not a decimal number" +
                          (std::strchr(all.c_str(), ',') ? " (a decimal comma?)" : "") +
                          ": the image cannot be placed or its values known");
    }
    out = v;
    return true;
}

DcmItem* firstItem(DcmItem* parent, const DcmTagKey& seq) {
    DcmItem* item = nullptr;
    if (parent && parent->findAndGetSequenceItem(seq, item, 0).good()) return item;
    return nullptr;
}

// Reads position/orientation/spacing/rescale from an item (a dataset or a functional group),
// leaving fields it does not find unchanged.
void readPlane(DcmItem* item, FrameGeometry& g) {
    if (!item) return;
    double v[6];
    if (number(item, DCM_ImagePositionPatient, v[0], 0) && number(item, DCM_ImagePositionPatient, v[1], 1) &&
        number(item, DCM_ImagePositionPatient, v[2], 2)) {
        g.hasPosition = true;
        g.position = {v[0], v[1], v[2]};
    }
    bool ok = true;
    for (unsigned long i = 0; i < 6 && ok; ++i) ok = number(item, DCM_ImageOrientationPatient, v[i], i);
    if (ok) {
        g.hasOrientation = true;
        g.rowDirection = {v[0], v[1], v[2]};
        g.columnDirection = {v[3], v[4], v[5]};
    }
    if (number(item, DCM_PixelSpacing, v[0], 0) && number(item, DCM_PixelSpacing, v[1], 1) && v[0] > 0 && v[1] > 0) {
        g.hasSpacing = true;
        g.pixelSpacing = {v[0], v[1]};
    }
    if (number(item, DCM_RescaleSlope, v[0]) && v[0] != 0.0) g.rescaleSlope = v[0];
    if (number(item, DCM_RescaleIntercept, v[0])) g.rescaleIntercept = v[0];
    if (std::string type = text(item, DCM_RescaleType); !type.empty()) g.rescaleType = type;
}

bool integer(DcmItem* item, const DcmTagKey& key, int& out) {
    Sint32 v = 0;
    if (item && item->findAndGetSint32(key, v).good()) {
        out = v;
        return true;
    }
    Uint32 u = 0;
    if (item && item->findAndGetUint32(key, u).good() && u <= 0x7fffffffu) {
        out = int(u);
        return true;
    }
    return false;
}

// Reads what tells images at one position apart (FrameDimensions) from an item: the classic
// attributes of a dataset, or the enhanced functional groups of a frame.
void readDimensions(DcmItem* item, FrameDimensions& d) {
    if (!item) return;
    double v = 0;
    int i = 0;
    if (const std::string t = text(item, DCM_ImageType); !t.empty()) d.imageType = t;
    if (integer(item, DCM_EchoNumbers, i)) d.echoNumber = i;
    if (number(item, DCM_EchoTime, v)) d.echoTime = v;
    if (number(item, DCM_DiffusionBValue, v)) d.bValue = v;
    double g[3];
    if (number(item, DCM_DiffusionGradientOrientation, g[0], 0) && number(item, DCM_DiffusionGradientOrientation, g[1], 1) &&
        number(item, DCM_DiffusionGradientOrientation, g[2], 2))
        d.gradient = glm::dvec3(g[0], g[1], g[2]);
    if (integer(item, DCM_TemporalPositionIdentifier, i)) d.temporalPosition = i;
    if (number(item, DCM_TriggerTime, v)) d.triggerTime = v;
    if (integer(item, DCM_AcquisitionNumber, i)) d.acquisitionNumber = i;
}

void readFrameDimensions(DcmItem* group, FrameDimensions& d) {
    if (!group) return;
    if (DcmItem* content = firstItem(group, DCM_FrameContentSequence)) {
        int i = 0;
        if (integer(content, DCM_TemporalPositionIndex, i)) d.temporalPosition = i;
        if (const std::string s = text(content, DCM_StackID); !s.empty()) d.stackId = s;
    }
    double v = 0;
    if (number(firstItem(group, DCM_MREchoSequence), DCM_EffectiveEchoTime, v)) d.echoTime = v;
    if (DcmItem* diffusion = firstItem(group, DCM_MRDiffusionSequence)) {
        readDimensions(diffusion, d);
        readDimensions(firstItem(diffusion, DCM_DiffusionGradientDirectionSequence), d);
    }
    if (number(firstItem(group, DCM_CardiacSynchronizationSequence), DCM_NominalCardiacTriggerDelayTime, v))
        d.triggerTime = v;
    for (const DcmTagKey& seq : {DCM_MRImageFrameTypeSequence, DCM_CTImageFrameTypeSequence})
        if (const std::string t = text(firstItem(group, seq), DCM_FrameType); !t.empty()) d.imageType = t;
}

void readFunctionalGroup(DcmItem* group, FrameGeometry& g) {
    readFrameDimensions(group, g.dimensions);
    readPlane(firstItem(group, DCM_PlanePositionSequence), g);
    readPlane(firstItem(group, DCM_PlaneOrientationSequence), g);
    readPlane(firstItem(group, DCM_PixelMeasuresSequence), g);
    readPlane(firstItem(group, DCM_PixelValueTransformationSequence), g);
}

/// The most frames one object may claim; the largest real multi-frame objects (breast
/// tomosynthesis, 4D ultrasound, whole enhanced CT series) stay far below it.
constexpr std::uint64_t kMaxFrames = 1u << 18;

/// A hostile NumberOfFrames must not size anything (the per-frame geometry below, the
/// assembler's slices): every frame takes room in the file, a whole frame when the pixels are
/// stored as they are, at least a fragment's 8-byte item header when encapsulated, and a
/// 1/1032 of a frame (deflate's best ratio) when the dataset is deflated.
/// One frame's bytes as stored natively; in bits first: 1-bit frames (a binary segmentation) are
/// packed, not one byte a pixel.
std::uint64_t nativeFrameBytes(const DicomInstance& p) {
    return (std::uint64_t(p.rows) * p.columns * std::max<std::uint16_t>(1, p.samplesPerPixel) *
                std::max<std::uint16_t>(1, p.bitsAllocated) + 7) / 8;
}

/// Pixels stored as they are take their whole size in the file: a file too short to hold them
/// is truncated, refused at import rather than when the series is built (where one such slice
/// had made the whole series unbuildable). The pixels start after the first PixelData tag in the
/// file's first MiB (an icon's nested one, earlier, only makes the bound laxer, never wrong).
void checkNativePixelBytes(DcmDataset* ds, const DicomInstance& p) {
    const DcmXfer xfer(ds->getOriginalXfer());
    // 4:2:2 colour stores two samples a pixel, not SamplesPerPixel (3): not checked.
    if (p.frames == 0 || p.floatPixelBits || xfer.isEncapsulated() || xfer.getStreamCompression() != ESC_none ||
        p.photometric.find("422") != std::string::npos)
        return;
    std::uint64_t start = 0;
    {  // read on in 64 KiB steps, to the tag: a header's few KiB, not the pixels
        std::ifstream f(p.path, std::ios::binary);
        const std::string tag = xfer.isBigEndian() ? std::string("\x7f\xe0\x00\x10", 4) : std::string("\xe0\x7f\x10\x00", 4);
        std::string head;
        std::size_t at = std::string::npos;
        while (at == std::string::npos && head.size() < (1u << 20) && f) {
            const std::size_t from = head.size() > 3 ? head.size() - 3 : 0;
            std::string chunk(1u << 16, '\0');
            f.read(chunk.data(), std::streamsize(chunk.size()));
            head.append(chunk.data(), std::size_t(f.gcount()));
            at = head.find(tag, std::max<std::size_t>(from, 132));
        }
        if (at == std::string::npos) return;
        start = at + 8;  // the shortest element header
    }
    // In bits over all frames: 1-bit frames (a binary segmentation) run on without padding.
    const std::uint64_t need = start + (std::uint64_t(p.frames) * p.rows * p.columns *
                                            std::max<std::uint16_t>(1, p.samplesPerPixel) *
                                            std::max<std::uint16_t>(1, p.bitsAllocated) + 7) / 8;
    if (p.fileSize < need)
        throw core::Error(p.path + ": the file's " + std::to_string(p.fileSize) + " bytes cannot hold its " +
                          std::to_string(need - start) + " bytes of pixel data after its header (" +
                          std::to_string(p.frames) + " frame(s) of " +
                          std::to_string(p.columns) + "x" + std::to_string(p.rows) + "): truncated");
}

void checkFrameCount(DcmDataset* ds, const DicomInstance& p) {
    if (p.frames <= 1) return;
    const DcmXfer xfer(ds->getOriginalXfer());
    const std::uint64_t frameBytes = nativeFrameBytes(p);
    std::uint64_t least = frameBytes;
    if (xfer.isEncapsulated()) least = 8;
    else if (xfer.getStreamCompression() != ESC_none) least = std::max<std::uint64_t>(1, frameBytes / 1032);
    const std::uint64_t fits = p.fileSize / std::max<std::uint64_t>(1, least);
    if (p.frames > fits)
        throw core::Error(p.path + ": NumberOfFrames " + std::to_string(p.frames) + " cannot be right: the file's " +
                          std::to_string(p.fileSize) + " bytes hold at most " + std::to_string(fits) + " frames of " +
                          std::to_string(p.columns) + "x" + std::to_string(p.rows));
    if (p.frames > kMaxFrames)
        throw core::Error(p.path + ": NumberOfFrames " + std::to_string(p.frames) + " is more than Holovox reads (" +
                          std::to_string(kMaxFrames) + ")");
}

void fromDataset(DcmDataset* ds, DcmMetaInfo* meta, DicomInstance& p) {
    p.sopClassUid = text(ds, DCM_SOPClassUID);
    if (p.sopClassUid.empty()) p.sopClassUid = text(meta, DCM_MediaStorageSOPClassUID);
    p.sopInstanceUid = text(ds, DCM_SOPInstanceUID);
    if (p.sopInstanceUid.empty()) p.sopInstanceUid = text(meta, DCM_MediaStorageSOPInstanceUID);
    p.transferSyntaxUid = DcmXfer(ds->getOriginalXfer()).getXferID();
    p.patientName = text(ds, DCM_PatientName);
    p.patientId = text(ds, DCM_PatientID);
    p.patientBirthDate = text(ds, DCM_PatientBirthDate);
    p.patientSex = text(ds, DCM_PatientSex);
    p.studyInstanceUid = text(ds, DCM_StudyInstanceUID);
    p.studyDate = text(ds, DCM_StudyDate);
    p.studyTime = text(ds, DCM_StudyTime);
    p.studyDescription = text(ds, DCM_StudyDescription);
    p.accessionNumber = text(ds, DCM_AccessionNumber);
    p.seriesInstanceUid = text(ds, DCM_SeriesInstanceUID);
    p.modality = text(ds, DCM_Modality);
    p.seriesDescription = text(ds, DCM_SeriesDescription);
    p.bodyPartExamined = text(ds, DCM_BodyPartExamined);
    p.frameOfReferenceUid = text(ds, DCM_FrameOfReferenceUID);
    p.referencedSeriesUid = referencedSeries(ds, p.sopClassUid);
    Sint32 i32 = 0;
    if (ds->findAndGetSint32(DCM_SeriesNumber, i32).good()) p.seriesNumber = i32;
    if (ds->findAndGetSint32(DCM_InstanceNumber, i32).good()) p.instanceNumber = i32;
    Uint16 u16 = 0;
    if (ds->findAndGetUint16(DCM_Rows, u16).good()) p.rows = u16;
    if (ds->findAndGetUint16(DCM_Columns, u16).good()) p.columns = u16;
    if (ds->findAndGetUint16(DCM_SamplesPerPixel, u16).good()) p.samplesPerPixel = u16;
    if (ds->findAndGetUint16(DCM_BitsAllocated, u16).good()) p.bitsAllocated = u16;
    if (ds->findAndGetUint16(DCM_BitsStored, u16).good()) p.bitsStored = u16;
    if (ds->findAndGetUint16(DCM_HighBit, u16).good()) p.highBit = u16;
    if (ds->findAndGetUint16(DCM_PixelRepresentation, u16).good()) p.pixelRepresentation = u16;
    if (p.bitsStored == 0) p.bitsStored = p.bitsAllocated;
    p.photometric = text(ds, DCM_PhotometricInterpretation);
    if (ds->findAndGetSint32(DCM_NumberOfFrames, i32).bad() || i32 < 1) i32 = 1;
    if (!ds->tagExists(DCM_PixelData)) {  // float images: the bits are given by the element itself
        if (ds->tagExists(DCM_FloatPixelData)) p.floatPixelBits = 32;
        if (ds->tagExists(DCM_DoubleFloatPixelData)) p.floatPixelBits = 64;
        if (p.floatPixelBits) p.bitsAllocated = p.bitsStored = std::uint16_t(p.floatPixelBits);
    }
    const bool pixels = ds->tagExists(DCM_PixelData) || p.floatPixelBits != 0;
    p.frames = (p.rows && p.columns && (pixels || p.bitsAllocated)) ? std::uint32_t(i32) : 0;
    checkFrameCount(ds, p);
    checkNativePixelBytes(ds, p);
    double d = 0;
    if (number(ds, DCM_SliceThickness, d)) p.sliceThickness = d;
    for (unsigned long i = 0; i < 8; ++i) {  // the presets a modality offers, first the default
        double centre = 0, width = 0;
        if (!number(ds, DCM_WindowCenter, centre, i, false) || !number(ds, DCM_WindowWidth, width, i, false)) break;
        if (!(width >= 1.0)) continue;  // PS3.3 C.11.2.1.2: a width below 1 is not a window
        OFString name;
        if (ds->findAndGetOFString(DCM_WindowCenterWidthExplanation, name, i).bad() || name.empty())
            name = ("DICOM " + std::to_string(i + 1)).c_str();
        p.windows.push_back({name.c_str(), centre, width});
    }
    {
        // PixelPaddingValue and its Range Limit are US or SS as PixelRepresentation says; a file
        // that writes them US beside signed pixels means their 16 bits as signed (63536: -2000).
        const auto padding = [&](const DcmTagKey& key) -> std::optional<double> {
            Uint16 pu = 0;
            Sint16 ps = 0;
            if (p.pixelRepresentation == 1 && ds->findAndGetSint16(key, ps).good()) return ps;
            if (ds->findAndGetUint16(key, pu).good())
                return p.pixelRepresentation == 1 ? double(std::int16_t(pu)) : double(pu);
            return std::nullopt;
        };
        p.pixelPadding = padding(DCM_PixelPaddingValue);
        if (p.pixelPadding) p.pixelPaddingLimit = padding(DCM_PixelPaddingRangeLimit);
    }
    FrameGeometry base;
    readPlane(ds, base);
    readDimensions(ds, base.dimensions);
    DcmItem* shared = firstItem(ds, DCM_SharedFunctionalGroupsSequence);
    readFunctionalGroup(shared, base);
    DcmSequenceOfItems* perFrame = nullptr;
    // RT dose grids scale their stored values by DoseGridScaling, one plane or many.
    if (double scaling = 0; number(ds, DCM_DoseGridScaling, scaling) && scaling > 0) base.rescaleSlope = scaling;
    if (ds->findAndGetSequence(DCM_PerFrameFunctionalGroupsSequence, perFrame).good() && perFrame &&
        p.frames >= 1) {  // an enhanced object of one frame has its position in its per-frame group too
        for (std::uint32_t f = 0; f < p.frames; ++f) {
            FrameGeometry g = base;
            if (f < perFrame->card()) readFunctionalGroup(perFrame->getItem(f), g);
            p.frameGeometry.push_back(g);
        }
    } else if (p.frames > 1 && ds->tagExists(DCM_GridFrameOffsetVector)) {
        // RT Dose: frames are planes along the normal (PS3.3 C.8.8.3.2). The offsets are relative
        // to ImagePositionPatient when the first is 0, else absolute coordinates along the normal
        // whose first is the plane at ImagePositionPatient; both are the first plane plus the
        // difference from the first offset.
        const glm::dvec3 n = glm::cross(base.rowDirection, base.columnDirection);
        double first = 0;
        const bool hasFirst = number(ds, DCM_GridFrameOffsetVector, first, 0);
        for (std::uint32_t f = 0; f < p.frames; ++f) {
            FrameGeometry g = base;
            double offset = 0;
            if (!hasFirst || !number(ds, DCM_GridFrameOffsetVector, offset, f)) g.hasPosition = false;
            g.position = base.position + n * (offset - first);
            p.frameGeometry.push_back(g);
        }
    } else if (p.frames > 0) {
        p.frameGeometry.assign(1, base);  // one plane for all frames
    }
}

bool hasPreamble(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    char buf[132] = {};
    f.read(buf, sizeof buf);
    return f.gcount() == 132 && std::memcmp(buf + 128, "DICM", 4) == 0;
}

DicomHeaderReader::Kind classify(const OFCondition& status, DcmFileFormat& file, bool preamble,
                                 const std::string& name, DicomInstance& out) {
    DcmDataset* ds = file.getDataset();
    const bool looksDicom = ds && (ds->tagExists(DCM_SOPClassUID) || ds->tagExists(DCM_StudyInstanceUID) ||
                                   ds->tagExists(DCM_PixelData));
    if (status.bad()) {
        if (!preamble && !looksDicom) return DicomHeaderReader::Kind::NotDicom;
        throw core::Error(name + ": broken DICOM file (" + status.text() + ")");
    }
    if (!looksDicom) {
        if (!preamble) return DicomHeaderReader::Kind::NotDicom;
        throw core::Error(name + ": DICOM file has no SOP Class, study or pixel data");
    }
    // Names and descriptions in another character set than UTF-8 are read as PS3.5 6.1 says:
    // Latin-1 bytes had been stored and shown as they were, and one patient written in two
    // character sets had become two.
    DatasetText::toUtf8(*ds);
    try {
        fromDataset(ds, file.getMetaInfo(), out);
    } catch (const core::Error& e) {  // a malformed value: named with its file
        const std::string what = e.what();
        throw core::Error(what.rfind(name, 0) == 0 ? what : name + ": " + what);
    }
    if (out.sopInstanceUid.empty()) throw core::Error(name + ": DICOM file has no SOP Instance UID");
    return DicomHeaderReader::Kind::Dicom;
}
}  // namespace

DicomHeaderReader::Kind DicomHeaderReader::read(const std::string& path, DicomInstance& out) {
    DcmtkSetup::ensure();
    out = DicomInstance{};
    out.path = path;
    std::error_code ec;
    out.fileSize = std::filesystem::file_size(path, ec);
    if (ec) throw core::Error(path + ": cannot read (" + ec.message() + ")");
    const bool preamble = hasPreamble(path);
    if (!preamble && out.fileSize < 8) return Kind::NotDicom;
    try {
        DcmFileFormat file;
        const OFCondition status = file.loadFileUntilTag(path.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength,
                                                         ERM_autoDetect, DCM_PixelData);
        const Kind k = classify(status, file, preamble, path, out);
        out.path = path;
        return k;
    } catch (const core::Error&) {
        throw;
    } catch (const std::exception& e) {
        // DCMTK 3.6.7 can throw from deep inside its parser on hostile input.
        throw core::Error(path + ": broken DICOM file (" + e.what() + ")");
    }
}

}  // namespace hvx::dicom
