#pragma once
#include <string>

#include <optional>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/SplitVoxelFitter.h"

namespace hvx::app {

/// Runs an octree build in the terminal: progress bar, Ctrl-C cancels cleanly, and a one-line
/// report (time, throughput, size) followed by the file's summary.
class OctreeBuildRunner {
public:
    /// With `split`, a split-voxel octree (core::SplitVoxelOctreeBuilder).
    static core::BuildReport run(core::VoxelSource& source, const std::string& output,
                                 const core::BuildOptions& options, bool printSummary,
                                 const std::optional<core::SplitVoxelOptions>& split = std::nullopt);
};

}  // namespace hvx::app
