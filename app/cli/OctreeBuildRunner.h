#pragma once
#include <string>

#include "core/octree/OctreeBuilder.h"

namespace hvx::app {

/// Runs an octree build in the terminal: progress bar, Ctrl-C cancels cleanly, and a one-line
/// report (time, throughput, size) followed by the file's summary.
class OctreeBuildRunner {
public:
    static core::BuildReport run(core::VoxelSource& source, const std::string& output,
                                 const core::BuildOptions& options, bool printSummary);
};

}  // namespace hvx::app
