#include "core/reference/VolumeHistogram.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/octree/OctreeLayout.h"

namespace hvx::core {

VolumeHistogram VolumeHistogram::compute(const OctreeReader& reader, int bins, std::size_t maxBricks) {
    VolumeHistogram h;
    const auto& g = reader.geometry();
    h.valueMin = g.valueMin;
    h.valueMax = g.valueMax > g.valueMin ? g.valueMax : g.valueMin + 1.0;
    h.counts.assign(std::size_t(std::max(1, bins)), 0);
    const OctreeLayout layout(g.dims, reader.brickSize());
    int level = 0;
    auto nodesAt = [&](int l) {
        const auto& n = layout.levelNodes(l);
        return std::size_t(n[0]) * n[1] * n[2];
    };
    while (level + 1 < layout.levelCount() && nodesAt(level) > maxBricks) ++level;
    h.level = level;
    const auto& dims = layout.levelDims(level);
    const auto& grid = layout.levelNodes(level);
    const std::uint32_t bs = reader.brickSize(), border = reader.border();
    const double scale = double(h.counts.size()) / (h.valueMax - h.valueMin);
    // Gradients: central differences over the level's spacing; the bins reach the steepest
    // step the value range allows over one voxel.
    const glm::dvec3 spacing = g.spacing * double(1u << level);
    const double minSpacing = std::min({spacing.x, spacing.y, spacing.z});
    h.gradientBinWidth = (h.valueMax - h.valueMin) / minSpacing / double(kGradientBins);
    h.gradientCounts.assign(kGradientBins, 0);
    for (std::uint32_t z = 0; z < grid[2]; ++z)
        for (std::uint32_t y = 0; y < grid[1]; ++y)
            for (std::uint32_t x = 0; x < grid[0]; ++x) {
                const Brick b = reader.readBrick(layout.nodeId(level, x, y, z));
                // Interior voxels that lie inside the level's volume (the last bricks are partial).
                const std::uint32_t nx = std::min(bs, dims[0] - x * bs), ny = std::min(bs, dims[1] - y * bs),
                                    nz = std::min(bs, dims[2] - z * bs);
                for (std::uint32_t k = 0; k < nz; ++k)
                    for (std::uint32_t j = 0; j < ny; ++j)
                        for (std::uint32_t i = 0; i < nx; ++i) {
                            const double v = b.value(i + border, j + border, k + border);
                            const auto bin = std::clamp(std::int64_t(std::floor((v - h.valueMin) * scale)), std::int64_t(0),
                                                        std::int64_t(h.counts.size()) - 1);
                            ++h.counts[std::size_t(bin)];
                            if (border == 0) continue;  // no neighbours across the brick's faces
                            const std::uint32_t x0 = i + border, y0 = j + border, z0 = k + border;
                            const glm::dvec3 grad((b.value(x0 + 1, y0, z0) - b.value(x0 - 1, y0, z0)) / (2.0 * spacing.x),
                                                  (b.value(x0, y0 + 1, z0) - b.value(x0, y0 - 1, z0)) / (2.0 * spacing.y),
                                                  (b.value(x0, y0, z0 + 1) - b.value(x0, y0, z0 - 1)) / (2.0 * spacing.z));
                            const auto gbin = std::min(std::size_t(glm::length(grad) / h.gradientBinWidth),
                                                       std::size_t(kGradientBins - 1));
                            ++h.gradientCounts[gbin];
                        }
            }
    return h;
}

std::pair<double, double> VolumeHistogram::bandAround(double value) const {
    if (counts.empty()) return {value, value};
    const double width = (valueMax - valueMin) / double(counts.size());
    const int bin = std::clamp(int((value - valueMin) / width), 0, int(counts.size()) - 1);
    const double floor = double(counts[std::size_t(bin)]) / 3.0;
    int a = bin, b = bin;
    const int limit = int(counts.size()) / 4;
    while (a > 0 && bin - a < limit && double(counts[std::size_t(a - 1)]) >= floor) --a;
    while (b + 1 < int(counts.size()) && b - bin < limit && double(counts[std::size_t(b + 1)]) >= floor) ++b;
    return {valueMin + a * width, valueMin + (b + 1) * width};
}

double VolumeHistogram::gradientPercentile(double p) const {
    std::uint64_t total = 0;
    for (auto c : gradientCounts) total += c;
    if (total == 0) return 0.0;
    const double target = std::clamp(p, 0.0, 1.0) * double(total);
    double seen = 0;
    for (std::size_t b = 0; b < gradientCounts.size(); ++b) {
        seen += double(gradientCounts[b]);
        if (seen >= target) return double(b + 1) * gradientBinWidth;
    }
    return double(gradientCounts.size()) * gradientBinWidth;
}

double VolumeHistogram::percentile(double p) const {
    std::uint64_t total = 0;
    for (auto c : counts) total += c;
    if (total == 0) return valueMin;
    const double target = std::clamp(p, 0.0, 1.0) * double(total);
    const double width = (valueMax - valueMin) / double(counts.size());
    double seen = 0;
    for (std::size_t b = 0; b < counts.size(); ++b) {
        const double next = seen + double(counts[b]);
        if (next >= target && counts[b] > 0)
            return valueMin + (double(b) + (target - seen) / double(counts[b])) * width;
        seen = next;
    }
    return valueMax;
}

}  // namespace hvx::core
