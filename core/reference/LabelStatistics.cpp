#include "core/reference/LabelStatistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/matrix.hpp>

#include "core/base/Error.h"
#include "core/base/JobContext.h"
#include "core/octree/OctreeLayout.h"
#include "core/reference/SliceSampler.h"
#include "core/streaming/BrickCache.h"

namespace hvx::core {

namespace {
struct Sums {
    bool approximate = false;
    std::uint64_t voxels = 0, sampled = 0;
    double sum = 0, sumSq = 0, min = std::numeric_limits<double>::infinity(), max = -std::numeric_limits<double>::infinity();
};
}  // namespace

LabelStatistics LabelStatistics::compute(const OctreeReader& image, const OctreeReader& labels, JobContext& job) {
    const auto& lg = labels.geometry();
    if (!lg.isLabel) throw Error(labels.path() + " is not a label map (build it with --labels)");
    const auto& ig = image.geometry();
    BrickCache cache(std::size_t(256) << 20);
    const SliceSampler sampler(image, cache);
    const OctreeLayout layout(lg.dims, labels.brickSize());
    const auto& grid = layout.levelNodes(0);
    const glm::dmat4 toPatient = lg.indexToPatient();
    const std::uint32_t bs = labels.brickSize(), border = labels.border();
    std::map<int, Sums> sums;
    const std::uint64_t total = std::uint64_t(grid[0]) * grid[1] * grid[2];
    std::uint64_t done = 0;
    // The image's level-0 bricks stored without their values (empty or 8-bit, and not constant):
    // a label sampled in one has approximate figures.
    const OctreeLayout imageLayout(ig.dims, image.brickSize());
    std::vector<bool> inexact(image.nodes().size(), false);
    bool approximate = false;
    for (std::size_t n = 0; n < image.nodes().size(); ++n) {
        const auto& r = image.nodes()[n];
        inexact[n] = r.level == 0 && (r.flags & (hvo::NodeEmpty | hvo::NodeLossy8)) && r.maxValue > r.minValue;
        approximate = approximate || inexact[n];
    }
    const glm::dmat4 toImage = glm::inverse(ig.indexToPatient());
    const auto sampledInexact = [&](const glm::dvec3& p) {  // any brick the trilinear sample reads from
        const glm::dvec3 c(toImage * glm::dvec4(p, 1.0));
        for (int corner = 0; corner < 8; ++corner) {
            std::uint32_t b[3];
            for (int a = 0; a < 3; ++a) {
                const double v = (corner >> a) & 1 ? std::ceil(c[a]) : std::floor(c[a]);
                b[a] = std::uint32_t(std::clamp(v, 0.0, double(ig.dims[std::size_t(a)] - 1))) / image.brickSize();
            }
            if (inexact[imageLayout.nodeId(0, b[0], b[1], b[2])]) return true;
        }
        return false;
    };
    for (std::uint32_t z = 0; z < grid[2]; ++z)
        for (std::uint32_t y = 0; y < grid[1]; ++y)
            for (std::uint32_t x = 0; x < grid[0]; ++x) {
                job.throwIfCancelled();
                job.report(double(done++) / double(total), "label statistics");
                const std::uint32_t node = layout.nodeId(0, x, y, z);
                const auto& record = labels.nodes()[node];
                if (record.minValue == 0 && record.maxValue == 0) continue;  // background only (labels may be negative)
                const Brick b = labels.readBrick(node);
                const std::uint32_t i0 = x * bs, j0 = y * bs, k0 = z * bs;
                for (std::uint32_t k = k0; k < std::min(k0 + bs, lg.dims[2]); ++k)
                    for (std::uint32_t j = j0; j < std::min(j0 + bs, lg.dims[1]); ++j)
                        for (std::uint32_t i = i0; i < std::min(i0 + bs, lg.dims[0]); ++i) {
                            const int l = int(std::lround(b.value(i - i0 + border, j - j0 + border, k - k0 + border)));
                            if (l == 0) continue;
                            Sums& s = sums[l];
                            ++s.voxels;
                            const glm::dvec3 p(toPatient * glm::dvec4(i, j, k, 1.0));
                            const double v = sampler.valueAt(p, 0);
                            if (std::isnan(v)) continue;
                            const double phys = v * ig.rescaleSlope + ig.rescaleIntercept;
                            if (approximate && !s.approximate) s.approximate = sampledInexact(p);
                            ++s.sampled;
                            s.sum += phys;
                            s.sumSq += phys * phys;
                            s.min = std::min(s.min, phys);
                            s.max = std::max(s.max, phys);
                        }
            }
    LabelStatistics out;
    out.units = ig.hounsfield() ? "HU" : "";
    // A voxel's volume is its parallelepiped's: a sheared grid (gantry tilt) holds less than the
    // product of its spacings.
    const double voxelMl = std::abs(glm::determinant(glm::dmat3(lg.indexToPatient()))) / 1000.0;
    std::string outside;
    for (const auto& [label, s] : sums) {
        Row r;
        r.voxels = s.voxels;
        r.volumeMl = double(s.voxels) * voxelMl;
        r.sampled = s.sampled;
        r.exact = !s.approximate;
        if (s.sampled > 0) {
            r.mean = s.sum / double(s.sampled);
            r.sd = std::sqrt(std::max(0.0, s.sumSq / double(s.sampled) - r.mean * r.mean));
            r.min = s.min;
            r.max = s.max;
        }
        if (s.sampled < s.voxels) outside += (outside.empty() ? "" : ", ") + std::to_string(label);
        out.rows[label] = r;
    }
    if (!outside.empty()) out.note = "label(s) " + outside + " reach outside the image: their means count only the voxels inside";
    std::string inexactLabels;
    for (const auto& [label, r] : out.rows)
        if (!r.exact) inexactLabels += (inexactLabels.empty() ? "" : ", ") + std::to_string(label);
    if (!inexactLabels.empty())
        out.note += std::string(out.note.empty() ? "" : "; ") + "label(s) " + inexactLabels +
                    " lie where the image stores bricks without their values (empty or 8-bit): their figures are "
                    "approximate (the exact column says which)";
    return out;
}

std::string LabelStatistics::csv(const LabelTable* table) const {
    std::string out = "label,name,voxels,volume_ml,voxels_in_image,mean,sd,min,max,units,exact\n";
    char buf[256];
    for (const auto& [label, r] : rows) {
        std::string name = "label " + std::to_string(label);
        if (const auto* e = table ? table->find(label) : nullptr) name = e->name;
        std::string quoted = "\"";
        for (const char c : name) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
        quoted += '"';
        if (r.sampled > 0)
            std::snprintf(buf, sizeof buf, ",%llu,%.6f,%llu,%.6g,%.6g,%.6g,%.6g,%s,%s\n", static_cast<unsigned long long>(r.voxels),
                          r.volumeMl, static_cast<unsigned long long>(r.sampled), r.mean, r.sd, r.min, r.max, units.c_str(),
                          r.exact ? "yes" : "no");
        else
            std::snprintf(buf, sizeof buf, ",%llu,%.6f,0,,,,,%s,yes\n", static_cast<unsigned long long>(r.voxels), r.volumeMl,
                          units.c_str());
        out += std::to_string(label) + "," + quoted + buf;
    }
    return out;
}

}  // namespace hvx::core
