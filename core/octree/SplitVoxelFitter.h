#pragma once
#include <cstdint>

#include "core/octree/SplitVoxel.h"

namespace hvx::core {

/// How split-voxels are made (`holovox-cli build --split-voxels`).
struct SplitVoxelOptions {
    std::uint32_t n = 2;        ///< voxels per split-voxel edge at the finest level (2..8)
    std::uint32_t overlap = 2;  ///< M: neighbour voxel layers each cell's fit also sees (0..4)
    /// Intensities: two clusters whose means differ by less than this (stored units) are one
    /// material, and the cell is uniform. Labels ignore it.
    double threshold = 0.0;
    bool labels = false;  ///< label volume: classes are the labels themselves (§4.4.1.1)
    /// Throws core::Error with a sentence naming the parameter and its range.
    void validate() const;
};

/// Fits one split-voxel to a window of samples (thesis §4.4.1): the cell's S³ interior samples
/// and `overlap` layers of neighbours on every side, x fastest. Labels: the two most frequent
/// labels of the window; intensities: two-means clustering seeded at the window's minimum and
/// maximum, each cluster's median its value. The plane passes through the point of Eq. 4.2
/// between the two classes' barycentres, normal along Eq. 4.1. The cell is uniform when one
/// class fills the window, when the barycentres lie within half a sample of each other (not
/// linearly separable), when the means are closer than the threshold, or when the plane misses
/// the cell (then the value of the side the cell lies on). A uniform cell of intensities takes
/// the mean of its interior samples, a uniform cell of labels their most frequent label.
///
/// Threading: const; fit may run on many threads at once.
class SplitVoxelFitter {
public:
    explicit SplitVoxelFitter(SplitVoxelOptions options);
    /// `interior` = S (samples per cell edge), `overlap` = M; window holds (S + 2M)³ samples.
    SplitVoxel fit(const float* window, std::uint32_t interior, std::uint32_t overlap) const;
    const SplitVoxelOptions& options() const { return options_; }

private:
    SplitVoxelOptions options_;
};

}  // namespace hvx::core
