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
    bool approximate = false;
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
                            ++s.sampled;
                            s.sum += phys;
                            s.sumSq += phys * phys;
                            s.min = std::min(s.min, phys);
                            s.max = std::max(s.max, phys);
                        }
            }
    for (const auto& n : image.nodes())
        approximate = approximate || (n.level == 0 && (n.flags & (hvo::NodeEmpty | hvo::NodeLossy8)) && n.maxValue > n.minValue);
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
    if (approximate)
        out.note += std::string(out.note.empty() ? "" : "; ") +
                    "the image stores some bricks without their values (empty or 8-bit): means there are approximate";
    return out;
}

std::string LabelStatistics::csv(const LabelTable* table) const {
    std::string out = "label,name,voxels,volume_ml,voxels_in_image,mean,sd,min,max,units\n";
    char buf[256];
    for (const auto& [label, r] : rows) {
        std::string name = "label " + std::to_string(label);
        if (const auto* e = table ? table->find(label) : nullptr) name = e->name;
        std::string quoted = "\"";
        for (const char c : name) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
        quoted += '"';
        if (r.sampled > 0)
            std::snprintf(buf, sizeof buf, ",%llu,%.6f,%llu,%.6g,%.6g,%.6g,%.6g,%s\n", static_cast<unsigned long long>(r.voxels),
                          r.volumeMl, static_cast<unsigned long long>(r.sampled), r.mean, r.sd, r.min, r.max, units.c_str());
        else
            std::snprintf(buf, sizeof buf, ",%llu,%.6f,0,,,,,%s\n", static_cast<unsigned long long>(r.voxels), r.volumeMl,
                          units.c_str());
        out += std::to_string(label) + "," + quoted + buf;
    }
    return out;
}

}  // namespace hvx::core
