#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "core/base/JobContext.h"
#include "core/octree/SplitVoxelFitter.h"
#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// One level of a split-voxel hierarchy held in memory: a grid of split-voxels, each standing
/// for cellVoxels() source voxels per edge. Cell (x, y, z) covers the source's continuous index
/// range [x·c − ½, (x+1)·c − ½) along i (likewise j, k), c = cellVoxels(), voxel centres at
/// integer indices. Level 0 is fitted to the volume's voxels (§4.4.1); each coarser level to a
/// resampling of the finer one (§4.4.2): every finer cell is sampled at 2³ points, each taking
/// the value of the side of its plane it falls on, and the coarser cell is fitted to those, so
/// that filtering never blurs across a plane.
///
/// The whole level lives in memory (tests, benchmarks, the comparison renders); the octree
/// build cuts the same windows from its slabs.
///
/// Threading: build and coarser run their fits on ThreadPool::shared(); the result is immutable.
class SplitVoxelGrid {
public:
    using Dims = std::array<std::uint32_t, 3>;
    SplitVoxelGrid() = default;
    SplitVoxelGrid(Dims cells, std::uint32_t cellVoxels);

    /// Level 0 of `source` (read whole). Throws core::Error for options out of range or a
    /// source whose values are not 8- or 16-bit integers; core::Cancelled.
    static SplitVoxelGrid build(VoxelSource& source, const SplitVoxelOptions& options, JobContext& job);
    /// The next coarser level (cells of twice the edge).
    SplitVoxelGrid coarser(const SplitVoxelOptions& options, JobContext& job) const;

    const Dims& dims() const { return dims_; }
    std::uint32_t cellVoxels() const { return cellVoxels_; }
    const SplitVoxel& at(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
        return cells_[(std::size_t(z) * dims_[1] + y) * dims_[0] + x];
    }
    SplitVoxel& at(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
        return cells_[(std::size_t(z) * dims_[1] + y) * dims_[0] + x];
    }
    /// The reconstructed value at a continuous source index (clamped into the grid).
    float valueAt(const glm::dvec3& index) const;
    /// The intensity threshold this level was fitted with (stored units).
    double threshold() const { return threshold_; }
    /// How many cells are split (not uniform).
    std::size_t splitCells() const;

private:
    Dims dims_{0, 0, 0};
    std::uint32_t cellVoxels_ = 1;
    std::vector<SplitVoxel> cells_;
    double threshold_ = 0.0;  // the intensity threshold the level was fitted with (stored units)
};

}  // namespace hvx::core
