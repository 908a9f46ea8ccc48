#include "dicom/SegmentationSource.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmdata/dcxfer.h>
#include <dcmtk/dcmiod/iodtypes.h>
#include <dcmtk/dcmfg/fginterface.h>
#include <dcmtk/dcmfg/fgpixmsr.h>
#include <dcmtk/dcmfg/fgplanor.h>
#include <dcmtk/dcmfg/fgplanpo.h>
#include <dcmtk/dcmfg/fgseg.h>
#include <dcmtk/dcmseg/segdoc.h>
#include <dcmtk/dcmseg/segment.h>
#include <dcmtk/dcmseg/segutils.h>
#include <glm/geometric.hpp>

#include "core/base/Error.h"
#include "dicom/DatasetText.h"
#include "dicom/DcmtkSetup.h"

namespace hvx::dicom {

namespace {
/// DICOM's CIELab encoding (PS3.3 C.10.7.1.1: L 0-100, a and b -128..127, scaled to 0-65535)
/// to 8-bit sRGB through XYZ with the D65 white, as dcmqi (3D Slicer's SEG reader) converts it.
std::array<std::uint8_t, 4> labToRgb(Uint16 L, Uint16 A, Uint16 B) {
    const double l = L * 100.0 / 65535.0, a = A * 255.0 / 65535.0 - 128, b = B * 255.0 / 65535.0 - 128;
    double y = (l + 16) / 116, x = a / 500 + y, z = y - b / 200;
    const auto f = [](double t) { return t * t * t > 0.008856 ? t * t * t : (t - 16.0 / 116) / 7.787; };
    x = 0.95047 * f(x), y = 1.0 * f(y), z = 1.08883 * f(z);
    const double rgb[3] = {x * 3.2406 + y * -1.5372 + z * -0.4986, x * -0.9689 + y * 1.8758 + z * 0.0415,
                           x * 0.0557 + y * -0.2040 + z * 1.0570};
    std::array<std::uint8_t, 4> out{0, 0, 0, 255};
    for (int i = 0; i < 3; ++i) {
        double c = rgb[i] > 0.0031308 ? 1.055 * std::pow(rgb[i], 1 / 2.4) - 0.055 : 12.92 * rgb[i];
        out[std::size_t(i)] = std::uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255));
    }
    return out;
}

struct FrameRef {
    std::size_t frame;
    std::uint16_t segment;
};
}  // namespace

/// DCMTK 3.6.7's DcmSegmentation::loadDataset loses the object it made when reading fails (it
/// deletes its null out-parameter instead of the object): the same steps here, with the object
/// owned whatever the outcome.
class OwnedSegmentation : public DcmSegmentation {
public:
    static OFCondition load(DcmDataset& ds, std::unique_ptr<DcmSegmentation>& out) {
        // RLE-compressed frames are decompressed first, as loadDataset does (deflate is undone
        // when the file is read).
        if (DcmXfer(ds.getOriginalXfer()).isEncapsulated() &&
            (ds.chooseRepresentation(EXS_LittleEndianExplicit, nullptr).bad() ||
             !ds.canWriteXfer(EXS_LittleEndianExplicit)))
            return IOD_EC_CannotDecompress;
        std::unique_ptr<OwnedSegmentation> seg(new OwnedSegmentation());
        const OFCondition result = seg->read(ds);
        if (result.good()) out = std::move(seg);
        return result;
    }
};

struct SegmentationSource::Impl {
    std::string path;
    DcmFileFormat file;
    std::unique_ptr<DcmSegmentation> seg;
    core::VolumeGeometry g;
    core::LabelTable table;
    bool fractional = false;
    double maxFraction = 1;
    Uint16 rows = 0, cols = 0;
    std::map<std::uint32_t, std::vector<FrameRef>> slices;  // slice index -> its frames, segments ascending
    std::vector<std::string> warnings;

    [[noreturn]] void fail(const std::string& what) const { throw core::Error(path + ": " + what); }

    /// One frame as one byte per pixel: 1 where the segment is.
    std::vector<std::uint8_t> mask(std::size_t frame) const {
        const DcmIODTypes::Frame* f = seg->getFrame(frame);
        const std::size_t n = std::size_t(rows) * cols;
        std::vector<std::uint8_t> out(n, 0);
        if (!f || !f->pixData) fail("frame " + std::to_string(frame + 1) + " has no pixel data");
        if (!fractional) {
            if (f->length * 8 < n) fail("frame " + std::to_string(frame + 1) + " is shorter than its rows and columns");
            DcmIODTypes::Frame* unpacked = DcmSegUtils::unpackBinaryFrame(f, rows, cols);
            if (!unpacked) fail("frame " + std::to_string(frame + 1) + " does not unpack");
            for (std::size_t i = 0; i < n; ++i) out[i] = unpacked->pixData[i] != 0;
            delete unpacked;
        } else {
            if (f->length < n) fail("frame " + std::to_string(frame + 1) + " is shorter than its rows and columns");
            for (std::size_t i = 0; i < n; ++i) out[i] = f->pixData[i] >= maxFraction / 2;
        }
        return out;
    }
};

bool SegmentationSource::isSegmentation(const std::string& path) {
    DcmtkSetup::ensure();
    DcmFileFormat ff;
    if (ff.loadFile(path.c_str(), EXS_Unknown, EGL_noChange, 256).bad()) return false;
    OFString sopClass;
    if (ff.getMetaInfo()->findAndGetOFString(DCM_MediaStorageSOPClassUID, sopClass).bad())
        ff.getDataset()->findAndGetOFString(DCM_SOPClassUID, sopClass);
    return sopClass == UID_SegmentationStorage;
}

SegmentationSource::SegmentationSource(const std::string& path) : impl_(std::make_unique<Impl>()) {
    DcmtkSetup::ensure();
    auto& m = *impl_;
    m.path = path;
    if (m.file.loadFile(path.c_str()).bad()) m.fail("not a readable DICOM file");
    DcmDataset& ds = *m.file.getDataset();
    DatasetText::toUtf8(ds);  // segment labels in the file's character set
    OFString sopClass;
    ds.findAndGetOFString(DCM_SOPClassUID, sopClass);
    if (sopClass != UID_SegmentationStorage) m.fail("not a DICOM Segmentation object (SOP class " + std::string(sopClass.c_str()) + ")");
    if (const OFCondition loaded = OwnedSegmentation::load(ds, m.seg); loaded.bad() || !m.seg)
        m.fail("the segmentation does not load (dcmseg: " + std::string(loaded.text()) + ")");
    m.fractional = m.seg->getSegmentationType() == DcmSegTypes::ST_FRACTIONAL;
    if (m.fractional) {
        Uint16 maxValue = 0;
        if (ds.findAndGetUint16(DCM_MaximumFractionalValue, maxValue).bad() || maxValue == 0)
            m.fail("a fractional segmentation without MaximumFractionalValue");
        m.maxFraction = maxValue;
        m.warnings.push_back("fractional segmentation: each segment is the voxels at or above half its maximum (" +
                             std::to_string(maxValue) + ")");
    }
    ds.findAndGetUint16(DCM_Rows, m.rows);
    ds.findAndGetUint16(DCM_Columns, m.cols);
    if (m.rows == 0 || m.cols == 0) m.fail("no Rows or Columns");
    const std::size_t frames = m.seg->getNumberOfFrames();
    if (frames == 0) m.fail("no frames");
    FGInterface& fg = m.seg->getFunctionalGroups();
    // Orientation and pixel spacing: the first frame's (shared in every SEG Holovox has met;
    // per-frame values that differ are refused below).
    auto* orient = dynamic_cast<FGPlaneOrientationPatient*>(fg.get(0, DcmFGTypes::EFG_PLANEORIENTPATIENT));
    auto* measures = dynamic_cast<FGPixelMeasures*>(fg.get(0, DcmFGTypes::EFG_PIXELMEASURES));
    if (!orient) m.fail("no ImageOrientationPatient (PlaneOrientationSequence): left and right would be a guess");
    if (!measures) m.fail("no PixelSpacing (PixelMeasuresSequence)");
    Float64 o[6];
    if (orient->getImageOrientationPatient(o[0], o[1], o[2], o[3], o[4], o[5]).bad()) m.fail("unreadable ImageOrientationPatient");
    Float64 rowSpacing = 0, colSpacing = 0, between = 0;
    if (measures->getPixelSpacing(rowSpacing, 0).bad() || measures->getPixelSpacing(colSpacing, 1).bad() ||
        !(rowSpacing > 0) || !(colSpacing > 0))
        m.fail("no usable PixelSpacing");
    measures->getSpacingBetweenSlices(between);
    for (const Float64 v : o)
        if (!std::isfinite(v)) m.fail("ImageOrientationPatient holds a value that is not a number: left and right would be a guess");
    if (!(glm::length(glm::dvec3(o[0], o[1], o[2])) > 1e-3 && glm::length(glm::dvec3(o[3], o[4], o[5])) > 1e-3))
        m.fail("ImageOrientationPatient's rows or columns have no direction");
    const glm::dvec3 r = glm::normalize(glm::dvec3(o[0], o[1], o[2])), c = glm::normalize(glm::dvec3(o[3], o[4], o[5]));
    if (std::abs(glm::dot(r, c)) > 1e-3) m.fail("ImageOrientationPatient's rows and columns are not perpendicular");
    const glm::dvec3 n = glm::cross(r, c);
    std::vector<glm::dvec3> positions(frames);
    std::vector<std::uint16_t> segments(frames);
    for (std::size_t f = 0; f < frames; ++f) {
        auto* pos = dynamic_cast<FGPlanePosPatient*>(fg.get(Uint32(f), DcmFGTypes::EFG_PLANEPOSPATIENT));
        Float64 x = 0, y = 0, z = 0;
        if (!pos || pos->getImagePositionPatient(x, y, z).bad())
            m.fail("frame " + std::to_string(f + 1) + " has no position (PlanePositionSequence): it cannot be placed");
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            m.fail("frame " + std::to_string(f + 1) + "'s position (PlanePositionSequence) is not three numbers: it cannot be placed");
        positions[f] = {x, y, z};
        auto* segFg = dynamic_cast<FGSegmentation*>(fg.get(Uint32(f), DcmFGTypes::EFG_SEGMENTATION));
        Uint16 number = 0;
        if (!segFg || segFg->getReferencedSegmentNumber(number).bad() || number == 0)
            m.fail("frame " + std::to_string(f + 1) + " names no segment (SegmentIdentificationSequence)");
        if (!m.seg->getSegment(number)) m.fail("frame " + std::to_string(f + 1) + " names segment " + std::to_string(number) + ", which the object does not define");
        segments[f] = number;
        auto* po = dynamic_cast<FGPlaneOrientationPatient*>(fg.get(Uint32(f), DcmFGTypes::EFG_PLANEORIENTPATIENT));
        Float64 p[6];
        if (po && po->getImageOrientationPatient(p[0], p[1], p[2], p[3], p[4], p[5]).good())
            for (int a = 0; a < 6; ++a)
                if (!(std::abs(p[a] - o[a]) <= 1e-4)) m.fail("frame " + std::to_string(f + 1) + " has another orientation than frame 1");
    }
    // Slices along the normal: the lowest frame first.
    std::vector<double> depth(frames);
    for (std::size_t f = 0; f < frames; ++f) depth[f] = glm::dot(positions[f], n);
    const std::size_t lowest = std::size_t(std::min_element(depth.begin(), depth.end()) - depth.begin());
    const double tol = 1e-3 + 0.01 * std::min(rowSpacing, colSpacing);
    for (std::size_t f = 0; f < frames; ++f) {
        const glm::dvec3 d = positions[f] - positions[lowest];
        if (glm::length(d - glm::dot(d, n) * n) > tol)
            m.fail("frame " + std::to_string(f + 1) + " lies off the line of frame " + std::to_string(lowest + 1) +
                   " (frames not stacked along one normal)");
    }
    std::vector<double> distinct = depth;
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end(), [](double a, double b) { return std::abs(a - b) < 1e-3; }),
                   distinct.end());
    if (!std::isfinite(between)) m.fail("SpacingBetweenSlices is not a number");
    for (std::size_t i = 1; i < distinct.size() && between > 0; ++i)
        if (distinct[i] - distinct[i - 1] < 0.99 * between)  // every frame would round onto one slice
            m.fail("frames lie " + std::to_string(distinct[i] - distinct[i - 1]) + " mm apart, closer than its SpacingBetweenSlices (" +
                   std::to_string(between) + " mm)");
    double step = between > 0 ? between : 0;
    if (step == 0)
        for (std::size_t i = 1; i < distinct.size(); ++i)
            step = step == 0 ? distinct[i] - distinct[i - 1] : std::min(step, distinct[i] - distinct[i - 1]);
    if (step == 0) {  // one plane: its thickness, else 1 mm
        Float64 thickness = 0;
        measures->getSliceThickness(thickness);
        step = thickness > 0 ? thickness : 1.0;
    }
    std::uint32_t maxSlice = 0;
    for (std::size_t f = 0; f < frames; ++f) {
        const double k = (depth[f] - depth[lowest]) / step;
        const double kr = std::round(k);
        if (std::abs(k - kr) > 0.01)
            m.fail("frame " + std::to_string(f + 1) + " lies between the slices of a " + std::to_string(step) +
                   " mm grid (frames not on one slice grid)");
        if (!(kr <= 65535)) m.fail("frames span more than 65536 slices");
        const auto slice = std::uint32_t(kr);
        maxSlice = std::max(maxSlice, slice);
        m.slices[slice].push_back({f, segments[f]});
    }
    for (auto& [slice, list] : m.slices)
        std::stable_sort(list.begin(), list.end(), [](const FrameRef& a, const FrameRef& b) { return a.segment < b.segment; });
    auto& g = m.g;
    g.dims = {m.cols, m.rows, maxSlice + 1};
    g.spacing = {colSpacing, rowSpacing, step};
    g.direction = glm::dmat3(r, c, n);
    g.origin = positions[lowest];
    g.isLabel = true;
    g.modality = "SEG";
    OFString frame;
    m.seg->getFrameOfReference().getFrameOfReferenceUID(frame);
    g.frameOfReferenceUid = frame.c_str();
    // Segments, their names and colours.
    std::uint16_t maxSegment = 0;
    for (std::size_t s = 1; s <= m.seg->getNumberOfSegments() + 1000 && s <= 65535; ++s) {
        DcmSegment* segment = m.seg->getSegment(s);
        if (!segment) {
            if (s > m.seg->getNumberOfSegments()) break;
            continue;
        }
        OFString label;
        segment->getSegmentLabel(label);
        Uint16 L = 0, A = 0, B = 0;
        core::LabelTable::Entry e;
        e.name = label.empty() ? "segment " + std::to_string(s) : std::string(label.c_str());
        e.rgba = segment->getRecommendedDisplayCIELabValue(L, A, B).good() ? labToRgb(L, A, B)
                                                                           : std::array<std::uint8_t, 4>{0, 0, 0, 0};
        if (e.rgba[3] == 0) {  // no recommended colour: a generated one
            const auto generated = core::LabelTable::generated({int(s)});
            e.rgba = generated.find(int(s))->rgba;
        }
        m.table.set(int(s), e);
        maxSegment = std::uint16_t(s);
    }
    g.scalarType = maxSegment > 255 ? core::ScalarType::UInt16 : core::ScalarType::UInt8;
    g.valueMin = 0;
    g.valueMax = maxSegment;
    // Overlaps: counted once, here, so that the warning comes before a build.
    std::uint64_t overlaps = 0;
    for (const auto& [slice, list] : m.slices) {
        if (list.size() < 2) continue;
        std::vector<std::uint16_t> owner(std::size_t(m.rows) * m.cols, 0);
        for (const auto& fr : list) {
            const auto mask = m.mask(fr.frame);
            for (std::size_t i = 0; i < mask.size(); ++i)
                if (mask[i]) {
                    overlaps += owner[i] != 0 && owner[i] != fr.segment;
                    owner[i] = fr.segment;
                }
        }
    }
    if (overlaps)
        m.warnings.push_back(std::to_string(overlaps) + " voxel(s) belong to more than one segment: a label map holds one "
                             "label per voxel, the higher segment number is shown there");
}

SegmentationSource::~SegmentationSource() = default;

const core::VolumeGeometry& SegmentationSource::geometry() const { return impl_->g; }
std::string SegmentationSource::describe() const { return impl_->path; }
std::vector<std::string> SegmentationSource::warnings() const {
    std::vector<std::string> out;
    for (const auto& w : impl_->warnings) out.push_back(impl_->path + ": " + w);
    return out;
}
const core::LabelTable& SegmentationSource::table() const { return impl_->table; }

void SegmentationSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const auto& m = *impl_;
    const std::size_t n = std::size_t(m.rows) * m.cols;
    const bool wide = m.g.scalarType == core::ScalarType::UInt16;
    std::memset(dst, 0, n * count * (wide ? 2 : 1));
    for (std::uint32_t s = 0; s < count; ++s) {
        const auto it = m.slices.find(firstSlice + s);
        if (it == m.slices.end()) continue;
        for (const auto& fr : it->second) {
            const auto mask = m.mask(fr.frame);
            for (std::size_t i = 0; i < n; ++i) {
                if (!mask[i]) continue;
                if (wide) static_cast<std::uint16_t*>(dst)[s * n + i] = fr.segment;
                else static_cast<std::uint8_t*>(dst)[s * n + i] = std::uint8_t(fr.segment);
            }
        }
    }
}

}  // namespace hvx::dicom
