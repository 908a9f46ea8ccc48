#include "dicom/SeriesAssembler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include <glm/geometric.hpp>

#include "dicom/DicomSeriesSource.h"
#include "dicom/PersonName.h"
#include "dicom/VolumeSplitter.h"

namespace hvx::dicom {

namespace {
struct GroupKey {
    std::string series;
    std::string owner;  ///< patient ID, name and study UID: a series UID two patients share is never one stack
    std::string frame;  ///< Frame of Reference UID: two frames are two coordinate systems, never one stack
    std::uint16_t rows, columns, bits, signedness, samples;
    std::array<long, 6> iop;      ///< iop[0]: which plane of the series (samePlane), the rest 0
    std::array<long, 2> spacing;
    bool operator<(const GroupKey& o) const {
        return std::tie(series, owner, frame, rows, columns, bits, signedness, samples, iop, spacing) <
               std::tie(o.series, o.owner, o.frame, o.rows, o.columns, o.bits, o.signedness, o.samples, o.iop, o.spacing);
    }
};

/// A stack's plane: its orientation cosines and pixel spacing.
struct Plane {
    std::array<double, 6> iop;
    std::array<double, 2> spacing;
    /// Within 1e-4 of each other's cosines (about 0.006°) and 1e-4 mm of spacing: one plane.
    /// Rounding each to a grid had put values a hair apart (0.000049 and 0.000051) on two sides
    /// of a grid line, splitting one stack into interleaved halves.
    bool same(const Plane& o) const {
        for (int a = 0; a < 6; ++a)
            if (std::abs(iop[std::size_t(a)] - o.iop[std::size_t(a)]) > 1e-4) return false;
        for (int a = 0; a < 2; ++a)
            if (std::abs(spacing[std::size_t(a)] - o.spacing[std::size_t(a)]) > 1e-4) return false;
        return true;
    }
};

/// The angle between the row and column directions of ImageOrientationPatient, in degrees (0
/// when either is zero).
double orientationDegrees(const FrameGeometry& fg) {
    const double lr = glm::length(fg.rowDirection), lc = glm::length(fg.columnDirection);
    if (!(lr > 1e-6 && lc > 1e-6)) return 0.0;
    const double cosine = std::clamp(glm::dot(fg.rowDirection, fg.columnDirection) / (lr * lc), -1.0, 1.0);
    return std::acos(cosine) * 180.0 / M_PI;
}
/// How far they are from perpendicular. The standard asks for orthonormal cosines; written to
/// six decimals they are perpendicular to about 1e-4 degrees.
double orientationDegreesOff(const FrameGeometry& fg) { return std::abs(orientationDegrees(fg) - 90.0); }
/// Beyond a degree off perpendicular (4.5 mm across a 256 mm image) the header is broken: the
/// images are refused. Less, they are placed as stated (sheared), with a warning.
constexpr double kMostOrientationDegreesOff = 1.0;

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
    char buf[256];
    std::snprintf(buf, sizeof buf, f, a, b, c);
    return buf;
}

core::ScalarType storageType(const DicomInstance& in, bool applyRescale) {
    if (applyRescale || in.bitsAllocated > 16) return core::ScalarType::Float32;
    if (in.bitsAllocated <= 8) return in.pixelRepresentation ? core::ScalarType::Int16 : core::ScalarType::UInt8;
    return in.pixelRepresentation ? core::ScalarType::Int16 : core::ScalarType::UInt16;
}

/// Positions off the line from the first slice to the last by more than a tenth of a pixel are
/// named: such a stack is not one straight volume, and is placed by position along the line.
void checkOnLine(SeriesVolume& v, const glm::dvec3& k) {
    const auto& first = v.slices.front();
    const DicomInstance& in = v.instances[first.instance];
    const auto& fg = in.frame(first.frame);
    const double tolerance = 0.1 * std::min(fg.pixelSpacing.x, fg.pixelSpacing.y);
    double worst = 0;
    std::vector<std::string> off;
    for (const auto& s : v.slices) {
        const glm::dvec3 d = s.position - first.position;
        const double away = glm::length(d - glm::dot(d, k) * k);
        if (away <= tolerance) continue;
        worst = std::max(worst, away);
        if (off.size() < 5) off.push_back(std::to_string(v.instances[s.instance].instanceNumber));
        else if (off.size() == 5) off.push_back("...");
    }
    if (off.empty()) return;
    std::string names;
    for (const auto& o : off) names += (names.empty() ? "" : ", ") + o;
    v.warnings.push_back(fmt("slices lie off the stack's line by up to %.3g mm", worst) + " (instances " + names +
                         "): placed by their position along it");
}

void finishGeometry(SeriesVolume& v) {
    const DicomInstance& first = v.instances[v.slices.front().instance];
    const FrameGeometry& fg = first.frame(v.slices.front().frame);
    if (fg.hasOrientation) {
        const double off = orientationDegreesOff(fg);
        if (off > 0.01)
            v.warnings.push_back(fmt("ImageOrientationPatient's rows and columns are %.2f degrees apart, not "
                                     "perpendicular as the standard asks: the pixels are placed as stated (sheared)",
                                     orientationDegrees(fg)));
        const double lr = glm::length(fg.rowDirection), lc = glm::length(fg.columnDirection);
        if (std::abs(lr - 1.0) > 1e-3 || std::abs(lc - 1.0) > 1e-3)
            v.warnings.push_back(fmt("ImageOrientationPatient's directions are %.4g and %.4g long, not 1: taken as "
                                     "directions (normalised)", lr, lc));
    }
    glm::dvec3 r = glm::normalize(fg.rowDirection), c = glm::normalize(fg.columnDirection);
    const glm::dvec3 n = glm::normalize(glm::cross(r, c));
    auto& g = v.geometry;
    g.dims = {first.columns, first.rows, 1};
    g.spacing = {fg.pixelSpacing.y, fg.pixelSpacing.x, first.sliceThickness > 0 ? first.sliceThickness : 1.0};
    g.origin = v.slices.front().position;
    glm::dvec3 k = n;
    const std::size_t count = v.slices.size();
    if (count > 1) {
        std::vector<double> gaps;
        for (std::size_t s = 1; s < count; ++s) gaps.push_back(v.slices[s].along - v.slices[s - 1].along);
        std::vector<double> sorted = gaps;
        std::sort(sorted.begin(), sorted.end());
        const double median = sorted[sorted.size() / 2];
        const double minGap = sorted.front(), maxGap = sorted.back();
        const double span = v.slices.back().along - v.slices.front().along;
        const glm::dvec3 travel = v.slices.back().position - v.slices.front().position;
        k = glm::normalize(travel);
        v.tiltDegrees = std::acos(std::clamp(glm::dot(k, n), -1.0, 1.0)) * 180.0 / M_PI;
        if (v.tiltDegrees > 0.05 && !fg.hasOrientation)  // a tilt measured against axes that were assumed
            v.warnings.push_back(fmt("the slice positions run %.2f degrees off the assumed slice normal: the stack is "
                                     "kept sheared along them (no orientation to say whether that is a gantry tilt)",
                                     v.tiltDegrees));
        else if (v.tiltDegrees > 0.05)
            v.warnings.push_back(fmt("gantry tilt of %.2f degrees: the stack is kept sheared with its exact patient "
                                     "transform", v.tiltDegrees));
        const double tolerance = std::max(0.01 * median, 1e-3);
        double step = span / double(count - 1);
        std::uint32_t outSlices = std::uint32_t(count);
        if (maxGap - minGap > tolerance) {
            // Irregular: define the volume on a uniform grid at the regular (smallest common) spacing.
            step = std::max(minGap, median * 0.5);
            outSlices = std::uint32_t(std::lround(span / step)) + 1;
            step = span / double(outSlices - 1);
            v.resample = true;
            std::size_t missing = 0;
            for (double gap : gaps)
                if (gap > 1.5 * median) missing += std::size_t(std::lround(gap / median)) - 1;
            if (missing)
                v.warnings.push_back(fmt("%.0f missing slice(s): gaps up to %.3g mm where the spacing is %.3g mm; "
                                         "the gaps are interpolated", double(missing), maxGap, median));
            else
                v.warnings.push_back(fmt("non-uniform slice spacing (%.3g to %.3g mm): resampled to %.4g mm", minGap,
                                         maxGap, step));
        }
        checkOnLine(v, k);
        // Step along k that advances `step` along the normal.
        g.spacing.z = step / glm::dot(k, n);
        g.dims[2] = outSlices;
    }
    g.direction = glm::dmat3(r, c, k);
    // What was assumed comes first: it changes how every other figure must be read.
    if (!fg.hasOrientation)
        v.warnings.insert(v.warnings.begin(), "orientation unknown, assumed axial; left and right are not known "
                                              "(no ImageOrientationPatient)");
    if (!fg.hasSpacing) v.warnings.insert(v.warnings.begin(), "spacing unknown, assumed 1 mm (no PixelSpacing)");
    g.modality = first.modality.empty() ? "OT" : first.modality;
    // A CT's values are HU unless RescaleType names other units (dual-energy iodine, effective Z).
    if (g.modality == "CT") {
        std::set<std::string> types;
        for (const auto& s : v.slices) {
            const std::string& t = v.instances[s.instance].frame(s.frame).rescaleType;
            types.insert(t.empty() ? "HU" : t);
        }
        g.notHounsfield = types != std::set<std::string>{"HU"};
        if (g.notHounsfield) {
            std::string names;
            for (const auto& t : types) names += (names.empty() ? "" : ", ") + t;
            v.warnings.push_back("values in " + names + " (RescaleType), not Hounsfield units: measured without units, "
                                 "no HU windows or presets");
        }
    }
    // MONOCHROME1 (the lowest value white) is how to show the values, not what they are: a
    // stack that mixes the two keeps its values and is shown as MONOCHROME2, and says so.
    std::size_t inverted = 0;
    for (const auto& s : v.slices) inverted += v.instances[s.instance].photometric == "MONOCHROME1" ? 1 : 0;
    g.monochrome1 = inverted == v.slices.size();
    if (inverted && !g.monochrome1)
        v.warnings.push_back(fmt("%.0f of the %.0f slices are MONOCHROME1 (the lowest value white), the others "
                                 "MONOCHROME2: shown as MONOCHROME2 (higher values brighter); the values are as stored",
                                 double(inverted), double(v.slices.size())));
    g.spacingAssumed = !fg.hasSpacing;
    g.orientationAssumed = !fg.hasOrientation;
    g.windows = first.windows;
    g.frameOfReferenceUid = first.frameOfReferenceUid;
    // One rescale for every slice keeps stored values; otherwise convert to physical floats.
    bool sameRescale = true;
    for (const auto& s : v.slices)
        sameRescale = sameRescale && s.rescaleSlope == v.slices.front().rescaleSlope &&
                      s.rescaleIntercept == v.slices.front().rescaleIntercept;
    v.applyRescale = !sameRescale;
    if (v.applyRescale) v.warnings.push_back("rescale slope/intercept differ between slices: stored as float32 values");
    g.scalarType = storageType(first, v.applyRescale || first.bitsAllocated > 16);
    if (v.applyRescale || g.scalarType == core::ScalarType::Float32) {
        g.rescaleSlope = 1.0;
        g.rescaleIntercept = 0.0;
        v.applyRescale = true;
    } else {
        g.rescaleSlope = v.slices.front().rescaleSlope;
        g.rescaleIntercept = v.slices.front().rescaleIntercept;
    }
    // Padding (outside the scanned field) has no value of its own once stacked: say what it
    // became (-1024 HU may lie below what an unsigned type holds under the rescale).
    if (std::any_of(v.slices.begin(), v.slices.end(), [&](const SliceRef& s) { return v.instances[s.instance].pixelPadding.has_value(); })) {
        const double value = DicomSeriesSource::paddingValue(v);
        const std::string what = "pixels marked as padding (outside the scanned field) are shown and measured as ";
        if (!g.hounsfield())
            v.warnings.push_back(what + fmt("%.6g, the lowest value the stored bits hold", value));
        else if (value == core::VolumeGeometry::kCtPaddingHu)
            v.warnings.push_back(what + "-1024 HU, air: a region over them counts them as air");
        else
            v.warnings.push_back(what + fmt("%.6g HU (-1024 HU, air, lies below what the stored type holds under "
                                            "this rescale): a region over them counts them at that value", value));
    }
}
}  // namespace

std::vector<SeriesVolume> SeriesAssembler::assemble(const std::vector<DicomInstance>& instances,
                                                    std::vector<std::string>& notes) {
    std::map<GroupKey, std::vector<VolumeSplitter::Member>> groups;
    std::map<GroupKey, std::vector<Plane>> planes;  // per key without its plane: the planes met, in order
    std::map<std::string, std::set<std::string>> sizesPerSeries;
    std::map<std::string, std::size_t> skipped;
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const auto& in = instances[i];
        if (in.sopClassUid == "1.2.840.10008.5.1.4.1.1.481.3") {  // RT Structure Set Storage
            ++skipped["RT structure sets (contours; drawn over their image as labels, not stacked as one)"];
            continue;
        }
        if (!in.hasPixels() || in.frameGeometry.empty()) {
            ++skipped[in.modality.empty() ? "objects without image data" : in.modality + " objects without image data"];
            continue;
        }
        if (in.samplesPerPixel != 1) {
            ++skipped["colour images (not volumes)"];
            continue;
        }
        // One sample per pixel, but an index into a colour table (PALETTE COLOR), not a value.
        if (!in.photometric.empty() && in.photometric != "MONOCHROME1" && in.photometric != "MONOCHROME2") {
            ++skipped["images of photometric interpretation " + in.photometric + " (colour-table indices, not values)"];
            continue;
        }
        // NM multi-frame objects are placed by their Detector Information Sequence (and, for
        // tomography, by rotation), which Holovox does not read: refused rather than stacked.
        if (in.sopClassUid == "1.2.840.10008.5.1.4.1.1.66.4") {  // Segmentation Storage: not an image
            ++skipped["segmentation objects (SEG; laid over their image as labels, not stacked as one)"];
            continue;
        }
        if (in.modality == "NM" && in.frames > 1) {
            ++skipped["NM multi-frame objects (placed by a Detector Information Sequence Holovox does not read yet)"];
            continue;
        }
        for (std::uint32_t f = 0; f < in.frames; ++f) {
            const auto& fg = in.frame(f);
            if (fg.hasOrientation && orientationDegreesOff(fg) > kMostOrientationDegreesOff) {
                ++skipped["images whose ImageOrientationPatient is not two perpendicular directions (a broken header: "
                          "nothing says how their pixels lie)"];
                continue;
            }
            GroupKey k{in.seriesInstanceUid, in.patientId + '\\' + personNameKey(in.patientName) + '\\' + in.studyInstanceUid,
                       in.frameOfReferenceUid, in.rows, in.columns, in.bitsAllocated, in.pixelRepresentation,
                       in.samplesPerPixel, {}, {}};
            const Plane plane{{fg.rowDirection.x, fg.rowDirection.y, fg.rowDirection.z, fg.columnDirection.x,
                               fg.columnDirection.y, fg.columnDirection.z},
                              {fg.pixelSpacing.x, fg.pixelSpacing.y}};
            auto& met = planes[k];
            std::size_t which = 0;
            while (which < met.size() && !met[which].same(plane)) ++which;
            if (which == met.size()) met.push_back(plane);
            k.iop[0] = long(which);
            groups[k].push_back({i, f});
            sizesPerSeries[in.seriesInstanceUid].insert(std::to_string(in.columns) + "x" + std::to_string(in.rows));
        }
    }
    for (const auto& [what, n] : skipped) notes.push_back(std::to_string(n) + " " + what + " skipped");

    std::map<std::string, int> stacksPerSeries;
    std::map<std::string, std::set<std::string>> whyStacks;  // series -> what differs between its stacks
    std::map<std::string, const GroupKey*> firstKey;
    for (const auto& [key, members] : groups) {
        ++stacksPerSeries[key.series];
        const GroupKey*& first = firstKey[key.series];
        if (!first) {
            first = &key;
            continue;
        }
        if (key.owner != first->owner) whyStacks[key.series].insert("patients or studies (a UID collision)");
        if (key.frame != first->frame) whyStacks[key.series].insert("frames of reference");
        if (std::tie(key.rows, key.columns, key.bits, key.signedness, key.samples, key.iop, key.spacing) !=
            std::tie(first->rows, first->columns, first->bits, first->signedness, first->samples, first->iop, first->spacing))
            whyStacks[key.series].insert("geometry");
    }
    std::map<std::string, int> stackIndex;
    std::vector<SeriesVolume> out;
    for (auto& [key, members] : groups) {
        const DicomInstance& ref = instances[members.front().first];
        // The group's own orientation (a three-plane localizer's frames differ from frame 0's).
        const FrameGeometry& rg =
            ref.frame(members.front().second);
        const glm::dvec3 n = glm::normalize(glm::cross(rg.rowDirection, rg.columnDirection));
        // The same instance found twice (two copies of a file) is one image.
        std::set<std::pair<std::string, std::uint32_t>> seen;
        std::size_t copies = 0;
        members.erase(std::remove_if(members.begin(), members.end(),
                                     [&](const VolumeSplitter::Member& m) {
                                         const bool copy = !seen.insert({instances[m.first].sopInstanceUid, m.second}).second;
                                         copies += copy ? 1 : 0;
                                         return copy;
                                     }),
                      members.end());
        std::string stackLabel;
        if (stacksPerSeries[key.series] > 1)
            stackLabel = " (stack " + std::to_string(++stackIndex[key.series]) + " of " +
                         std::to_string(stacksPerSeries[key.series]) + ")";
        const auto split = VolumeSplitter::split(instances, members, n);
        const std::string seriesName = (ref.modality.empty() ? std::string("OT") : ref.modality) + " #" +
                                       std::to_string(ref.seriesNumber) +
                                       (ref.seriesDescription.empty() ? "" : " " + ref.seriesDescription);
        for (const auto& why : split.refused) notes.push_back(seriesName + stackLabel + ": " + why);
        for (const auto& part : split.parts) {
            SeriesVolume v;
            v.seriesUid = key.series;
            v.varying = part.varying;
            std::map<std::size_t, std::size_t> local;
            bool missingPosition = false;
            // Images without a position among images with one cannot be placed: they are left
            // out (one had been put at z = its index, 10 cm away, and interpolated towards).
            std::vector<std::string> unplaced;
            const bool somePlaced = std::any_of(part.members.begin(), part.members.end(), [&](const auto& m) {
                return instances[m.first].frame(m.second).hasPosition;
            });
            for (const auto& [idx, frame] : part.members) {
                const auto& in = instances[idx];
                if (somePlaced && !in.frame(frame).hasPosition) {
                    unplaced.push_back(std::to_string(in.instanceNumber) + (in.frames > 1 ? " frame " + std::to_string(frame + 1) : ""));
                    continue;
                }
                if (!local.count(idx)) {
                    local[idx] = v.instances.size();
                    v.instances.push_back(in);
                }
                const auto& fg = in.frame(frame);
                missingPosition = missingPosition || !fg.hasPosition;
                SliceRef s;
                s.instance = local[idx];
                s.frame = frame;
                s.position = fg.hasPosition ? fg.position : glm::dvec3(0.0, 0.0, double(v.slices.size()));
                s.along = glm::dot(s.position, n);
                s.rescaleSlope = fg.rescaleSlope;
                s.rescaleIntercept = fg.rescaleIntercept;
                v.slices.push_back(s);
            }
            if (missingPosition)
                v.warnings.push_back("images have no ImagePositionPatient: stacked in file order with 1 mm spacing");
            if (!unplaced.empty()) {
                std::string names;
                for (std::size_t u = 0; u < unplaced.size() && u < 5; ++u) names += (u ? ", " : "") + unplaced[u];
                if (unplaced.size() > 5) names += ", ...";
                v.warnings.push_back(std::to_string(unplaced.size()) + " image(s) without ImagePositionPatient (instance " +
                                     names + ") left out: nothing says where they lie; the others are placed by theirs");
            }
            if (copies)
                v.warnings.push_back(std::to_string(copies) + " files are copies of instances already found (same SOP "
                                     "Instance UID): each instance is used once");
            std::stable_sort(v.slices.begin(), v.slices.end(),
                             [](const SliceRef& a, const SliceRef& b) { return a.along < b.along; });
            if (stacksPerSeries[key.series] > 1) {
                std::string sizes;
                for (const auto& sz : sizesPerSeries[key.series]) sizes += (sizes.empty() ? "" : ", ") + sz;
                std::string why;
                for (const auto& w : whyStacks[key.series]) why += (why.empty() ? "" : " and ") + w;
                v.warnings.push_back("series holds " + std::to_string(stacksPerSeries[key.series]) +
                                     " stacks of different " + why +
                                     (sizesPerSeries[key.series].size() > 1 ? " and mixed image sizes (" + sizes + ")" : "") +
                                     ": split into separate volumes");
            }
            finishGeometry(v);
            v.label = seriesName + stackLabel + (v.varying.empty() ? "" : " \u2014 " + v.varying);
            out.push_back(std::move(v));
        }
    }
    // Patient, then study, then series order, as a browser lists them.
    std::stable_sort(out.begin(), out.end(), [](const SeriesVolume& a, const SeriesVolume& b) {
        const auto& x = a.instances.front();
        const auto& y = b.instances.front();
        return std::tie(x.patientId, x.patientName, x.studyDate, x.studyInstanceUid, x.seriesNumber, a.seriesUid) <
               std::tie(y.patientId, y.patientName, y.studyDate, y.studyInstanceUid, y.seriesNumber, b.seriesUid);
    });
    return out;
}

}  // namespace hvx::dicom
