#include "dicom/StructureSetSource.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmrt/drtstrct.h>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"
#include "dicom/DatasetText.h"
#include "dicom/DcmtkSetup.h"

namespace hvx::dicom {

namespace {
/// A contour in the grid's index space: (i, j) per point, on slice k.
struct Polygon {
    int roi;
    std::vector<glm::dvec2> points;
};
}  // namespace

struct StructureSetSource::Impl {
    std::string path;
    core::VolumeGeometry g;
    core::LabelTable table;
    std::map<std::uint32_t, std::vector<Polygon>> slices;  // slice -> contours, ROIs ascending
    std::vector<std::string> warnings;

    [[noreturn]] void fail(const std::string& what) const { throw core::Error(path + ": " + what); }

    /// The ROI label of every voxel centre of slice k (even-odd per ROI, higher ROI on top).
    void fill(std::uint32_t k, std::vector<std::uint16_t>& out, std::uint64_t* overlaps) const {
        const auto it = slices.find(k);
        if (it == slices.end()) return;
        const std::uint32_t nx = g.dims[0], ny = g.dims[1];
        std::map<int, std::vector<const Polygon*>> byRoi;
        for (const auto& p : it->second) byRoi[p.roi].push_back(&p);
        std::vector<double> xs;
        for (const auto& [roi, polys] : byRoi)
            for (std::uint32_t j = 0; j < ny; ++j) {
                // Crossings of the row through the voxel centres y = j with every edge (an edge
                // counts when it spans y half-open, so a vertex on the row is counted once).
                xs.clear();
                const double y = j;
                for (const Polygon* p : polys)
                    for (std::size_t e = 0; e < p->points.size(); ++e) {
                        const glm::dvec2 a = p->points[e], b = p->points[(e + 1) % p->points.size()];
                        if ((a.y > y) == (b.y > y)) continue;
                        xs.push_back(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
                    }
                std::sort(xs.begin(), xs.end());
                for (std::size_t s = 0; s + 1 < xs.size(); s += 2) {
                    // A vertex far outside the image puts a crossing far outside it: clipped to
                    // the row before it becomes an index.
                    const double x0 = std::clamp(xs[s], -1.0, double(nx)), x1 = std::clamp(xs[s + 1], -1.0, double(nx));
                    const long from = std::max(0L, long(std::ceil(x0))), to = std::min(long(nx) - 1, long(std::ceil(x1)) - 1);
                    for (long i = from; i <= to; ++i) {
                        auto& v = out[std::size_t(j) * nx + std::size_t(i)];
                        if (overlaps && v != 0 && v != roi) ++*overlaps;
                        v = std::uint16_t(roi);
                    }
                }
            }
    }
};

bool StructureSetSource::isStructureSet(const std::string& path) {
    DcmtkSetup::ensure();
    DcmFileFormat ff;
    if (ff.loadFile(path.c_str(), EXS_Unknown, EGL_noChange, 256).bad()) return false;
    OFString sopClass;
    if (ff.getMetaInfo()->findAndGetOFString(DCM_MediaStorageSOPClassUID, sopClass).bad())
        ff.getDataset()->findAndGetOFString(DCM_SOPClassUID, sopClass);
    return sopClass == UID_RTStructureSetStorage;
}

StructureSetSource::StructureSetSource(const std::string& path, const core::VolumeGeometry& grid)
    : impl_(std::make_unique<Impl>()) {
    DcmtkSetup::ensure();
    auto& m = *impl_;
    m.path = path;
    DcmFileFormat file;
    if (file.loadFile(path.c_str()).bad()) m.fail("not a readable DICOM file");
    DatasetText::toUtf8(*file.getDataset());  // ROI names in the file's character set
    DRTStructureSetIOD rt;
    OFString sopClass;
    file.getDataset()->findAndGetOFString(DCM_SOPClassUID, sopClass);
    if (sopClass != UID_RTStructureSetStorage) m.fail("not an RT Structure Set (SOP class " + std::string(sopClass.c_str()) + ")");
    if (rt.read(*file.getDataset()).bad()) m.fail("the structure set does not read (dcmrt)");
    OFString frame;
    rt.getFrameOfReferenceUID(frame);
    if (frame.empty() && rt.getReferencedFrameOfReferenceSequence().getNumberOfItems() > 0)
        rt.getReferencedFrameOfReferenceSequence().getItem(0).getFrameOfReferenceUID(frame);
    if (!frame.empty() && !grid.frameOfReferenceUid.empty() && grid.frameOfReferenceUid != frame.c_str())
        m.fail("drawn in frame of reference " + std::string(frame.c_str()) + ", the image is in " +
               grid.frameOfReferenceUid + ": its contours would land in the wrong place");
    m.g = grid;
    m.g.isLabel = true;
    m.g.modality = "RTSTRUCT";
    m.g.rescaleSlope = 1;
    m.g.rescaleIntercept = 0;
    m.g.windows.clear();
    m.g.monochrome1 = false;
    m.g.frameOfReferenceUid = frame.empty() ? grid.frameOfReferenceUid : std::string(frame.c_str());
    // Names from StructureSetROISequence, colours from ROIContourSequence.
    std::map<int, std::string> names;
    auto& rois = rt.getStructureSetROISequence();
    for (std::size_t i = 0; i < rois.getNumberOfItems(); ++i) {
        Sint32 number = 0;
        OFString name;
        rois.getItem(i).getROINumber(number);
        rois.getItem(i).getROIName(name);
        names[int(number)] = name.c_str();
    }
    const glm::dmat4 toIndex = glm::inverse(grid.indexToPatient());
    const double nk = double(grid.dims[2]);
    std::map<std::string, int> beyond, open;
    int maxRoi = 0;
    auto& contours = rt.getROIContourSequence();
    for (std::size_t r = 0; r < contours.getNumberOfItems(); ++r) {
        auto& item = contours.getItem(r);
        Sint32 number = 0;
        item.getReferencedROINumber(number);
        if (number <= 0 || number > 65535) m.fail("ROI number " + std::to_string(number) + " cannot be a label (1-65535)");
        const std::string name = names.count(number) ? names[number] : "ROI " + std::to_string(number);
        core::LabelTable::Entry e;
        e.name = name;
        Sint32 rgb[3] = {0, 0, 0};
        bool coloured = true;
        for (unsigned long c = 0; c < 3; ++c) coloured = coloured && item.getROIDisplayColor(rgb[c], c).good();
        e.rgba = coloured ? std::array<std::uint8_t, 4>{std::uint8_t(std::clamp(rgb[0], 0, 255)),
                                                        std::uint8_t(std::clamp(rgb[1], 0, 255)),
                                                        std::uint8_t(std::clamp(rgb[2], 0, 255)), 255}
                          : core::LabelTable::generated({int(number)}).find(int(number))->rgba;
        m.table.set(int(number), e);
        maxRoi = std::max(maxRoi, int(number));
        auto& seq = item.getContourSequence();
        for (std::size_t c = 0; c < seq.getNumberOfItems(); ++c) {
            auto& contour = seq.getItem(c);
            OFString type;
            contour.getContourGeometricType(type);
            if (type != "CLOSED_PLANAR") {
                ++open[name];
                continue;
            }
            OFVector<Float64> data;
            contour.getContourData(data);
            if (data.size() < 9 || data.size() % 3)
                m.fail("a contour of " + name + " has " + std::to_string(data.size()) +
                       " coordinates: a closed contour needs at least three points (x, y, z each)");
            Polygon poly{int(number), {}};
            double kMin = 1e300, kMax = -1e300;
            for (std::size_t p = 0; p < data.size(); p += 3) {
                if (!std::isfinite(data[p]) || !std::isfinite(data[p + 1]) || !std::isfinite(data[p + 2]))
                    m.fail("a contour of " + name + " has a point whose coordinates are not all numbers (point " +
                           std::to_string(p / 3 + 1) + ")");
                const glm::dvec4 idx = toIndex * glm::dvec4(data[p], data[p + 1], data[p + 2], 1.0);
                if (!(std::abs(idx.x) < 1e7 && std::abs(idx.y) < 1e7 && std::abs(idx.z) < 1e7))
                    m.fail("a contour of " + name + " has a point more than ten million voxels from the image (point " +
                           std::to_string(p / 3 + 1) + "): not a position in it");
                poly.points.push_back({idx.x, idx.y});
                kMin = std::min(kMin, idx.z), kMax = std::max(kMax, idx.z);
            }
            if (kMax - kMin > 0.1)
                m.fail("a contour of " + name + " is not in one slice of the image (it spans " + std::to_string(kMax - kMin) +
                       " slices): contours must lie in the image's slice planes");
            const double k = std::round((kMin + kMax) / 2);
            if (std::abs((kMin + kMax) / 2 - k) > 0.1)
                m.fail("a contour of " + name + " lies between two slices of the image");
            if (k < 0 || k >= nk) {
                ++beyond[name];
                continue;
            }
            m.slices[std::uint32_t(k)].push_back(std::move(poly));
        }
    }
    if (m.table.entries().empty()) m.fail("no ROI to draw");
    for (const auto& [name, n] : beyond)
        m.warnings.push_back(std::to_string(n) + " contour(s) of " + name + " lie past the image's slices: left out");
    for (const auto& [name, n] : open)
        m.warnings.push_back(std::to_string(n) + " contour(s) of " + name + " are points or open: not filled");
    m.g.scalarType = maxRoi > 255 ? core::ScalarType::UInt16 : core::ScalarType::UInt8;
    m.g.valueMin = 0;
    m.g.valueMax = maxRoi;
    std::uint64_t overlaps = 0;
    std::vector<std::uint16_t> plane(std::size_t(grid.dims[0]) * grid.dims[1]);
    for (const auto& [k, polys] : m.slices) {
        std::fill(plane.begin(), plane.end(), 0);
        m.fill(k, plane, &overlaps);
    }
    if (overlaps)
        m.warnings.push_back(std::to_string(overlaps) + " voxel(s) lie in more than one ROI: a label map holds one label "
                             "per voxel, the higher ROI number is shown there");
}

StructureSetSource::~StructureSetSource() = default;
const core::VolumeGeometry& StructureSetSource::geometry() const { return impl_->g; }
std::string StructureSetSource::describe() const { return impl_->path; }
const core::LabelTable& StructureSetSource::table() const { return impl_->table; }
std::vector<std::string> StructureSetSource::warnings() const {
    std::vector<std::string> out;
    for (const auto& w : impl_->warnings) out.push_back(impl_->path + ": " + w);
    return out;
}

void StructureSetSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const auto& m = *impl_;
    const std::size_t n = std::size_t(m.g.dims[0]) * m.g.dims[1];
    const bool wide = m.g.scalarType == core::ScalarType::UInt16;
    std::vector<std::uint16_t> plane(n);
    for (std::uint32_t s = 0; s < count; ++s) {
        std::fill(plane.begin(), plane.end(), 0);
        m.fill(firstSlice + s, plane, nullptr);
        for (std::size_t i = 0; i < n; ++i) {
            if (wide) static_cast<std::uint16_t*>(dst)[s * n + i] = plane[i];
            else static_cast<std::uint8_t*>(dst)[s * n + i] = std::uint8_t(plane[i]);
        }
    }
}

}  // namespace hvx::dicom
