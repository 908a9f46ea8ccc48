#pragma once
#include <cstdint>
#include <optional>

#include "core/octree/SplitVoxel.h"

namespace hvx::core {

/// How split-voxels are made (`holovox-cli build --split-voxels`).
struct SplitVoxelOptions {
    std::uint32_t n = 2;        ///< voxels per split-voxel edge at the finest level (2..8)
    std::uint32_t overlap = 2;  ///< M: neighbour voxel layers each cell's fit also sees (0..4)
    /// Intensities: two clusters whose means differ by less than this (stored units) are one
    /// material, and the cell is uniform. Labels ignore it. Unset: 2 % of the stored range the
    /// level-0 build finds in the volume (SplitVoxelGrid::build).
    std::optional<double> threshold;
    bool labels = false;  ///< label volume: classes are the labels themselves (§4.4.1.1)
    /// Throws core::Error with a sentence naming the parameter and its range.
    void validate() const;
};

/// Fits one split-voxel to a window of samples (thesis §4.4.1): the cell's S³ interior samples
/// and `overlap` layers of neighbours on every side, x fastest. The cell's own samples choose its
/// two materials: labels, the two most frequent of the interior; intensities, two-means
/// clustering of the interior seeded at its extremes, each cluster's median its value. The
/// window's samples of those two materials (a sample of a third one counts for neither) place
/// the plane: Eqs. 4.1–4.2 from their barycentres, refined (Fisher's direction, the offset that
/// misplaces fewest samples). The cell is uniform when its interior holds one material (or
/// intensities within the threshold: their mean), when the classes are not separable (the
/// interior's larger class), or when the plane misses the cell (the side it lies on).
/// The thesis chooses the materials over the whole window; here the interior does, so that a
/// thin structure inside the cell is not outvoted by a material of the overlap.
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
