#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "core/octree/OctreeReader.h"

namespace hvx::core {

/// A histogram of a volume's stored values over [valueMin, valueMax], read from the finest
/// octree level that has at most `maxBricks` nodes (a coarse level averages, so it is an
/// approximation that costs a few bricks, never the whole volume). Empty bricks count their
/// constant value for every interior voxel.
struct VolumeHistogram {
    double valueMin = 0, valueMax = 1;
    int level = 0;
    std::vector<std::uint64_t> counts;
    /// Gradient magnitudes |∇f| (stored units per mm, central differences at the level read)
    /// in kGradientBins bins of gradientBinWidth from 0 (gradient opacity's editor row).
    static constexpr int kGradientBins = 1024;
    double gradientBinWidth = 1.0;
    std::vector<std::uint64_t> gradientCounts;

    /// The gradient magnitude below which a fraction `p` of the voxels lie (0 when none).
    double gradientPercentile(double p) const;

    /// The band of values around `value` (stored units), grown over the histogram while the
    /// bins stay above a third of the picked bin's count and at most a quarter of the bins
    /// away on each side (region growing, as Huang's band picker). [value, value] when empty.
    std::pair<double, double> bandAround(double value) const;

    /// The stored value below which a fraction `p` (0..1) of the voxels lie, interpolated
    /// within the bin; valueMin when empty.
    double percentile(double p) const;

    /// Throws core::Error when a brick cannot be read.
    static VolumeHistogram compute(const OctreeReader& reader, int bins = 256, std::size_t maxBricks = 512);
};

}  // namespace hvx::core
