#pragma once
#include <string>

#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/SplitVoxelFitter.h"
#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Builds a split-voxel octree (.hvo version 2, thesis ch. 4): level 0 fitted to the volume's
/// voxels, each coarser level to the finer one (the windows of SplitVoxelGrid, resampled at 2³
/// points per finer cell), cut into bricks of brickSize³ cells over the octree layout of the
/// cell grid, each cell encoded (SplitVoxel::encode), each brick compressed and checksummed like
/// voxel bricks, every node with the smallest and largest value of its subtree. Written under a
/// temporary name and renamed (AtomicFileWriter): a failed or cancelled build leaves nothing.
///
/// Streams like OctreeBuilder: the volume is read slab by slab along k, each level keeps only
/// the rows of cells its bricks and the coarser level's fits still need, and bricks are written
/// as their rows complete, so memory is O(width × height × (brick + N + overlap)) at any depth.
/// Intensities without a threshold are read twice (the first pass finds their range).
///
/// Threading: build() runs on the calling (job) thread; fits run on ThreadPool::shared().
class SplitVoxelOctreeBuilder {
public:
    /// Throws core::Error for options out of range (brick size 4..256; split options as
    /// SplitVoxelOptions::validate; lossy storage and empty thresholds do not apply).
    SplitVoxelOctreeBuilder(BuildOptions build, SplitVoxelOptions split);
    /// Builds `output`; throws core::Error naming the input or output, or core::Cancelled.
    BuildReport build(VoxelSource& source, const std::string& output, JobContext& job);

private:
    BuildOptions build_;
    SplitVoxelOptions split_;
};

}  // namespace hvx::core
