#include "app/cli/OctreeBuildRunner.h"

#include <cstdio>

#include "app/cli/ProgressBar.h"
#include "app/cli/SignalCancel.h"
#include "core/octree/OctreeReader.h"
#include "core/octree/OctreeSummary.h"
#include "core/octree/SplitVoxelOctreeBuilder.h"

namespace hvx::app {

core::BuildReport OctreeBuildRunner::run(core::VoxelSource& source, const std::string& output,
                                         const core::BuildOptions& options, bool printSummary,
                                         const std::optional<core::SplitVoxelOptions>& split) {
    ProgressBar bar("build");
    core::JobContext job(bar.observer());
    SignalCancel cancelOnSignal(job);
    const core::BuildReport r = split ? core::SplitVoxelOctreeBuilder(options, *split).build(source, output, job)
                                      : core::OctreeBuilder(options).build(source, output, job);
    bar.finish();
    std::printf("built %s from %s in %.2f s (%.1f MB/s of input), %llu nodes\n", output.c_str(),
                source.describe().c_str(), r.seconds, double(r.inputBytes) / 1e6 / std::max(r.seconds, 1e-9),
                static_cast<unsigned long long>(r.nodeCount));
    if (printSummary) {
        const auto reader = core::OctreeReader::open(output, true);
        std::fputs(core::OctreeSummary::of(*reader).format(*reader).c_str(), stdout);
    }
    return r;
}

}  // namespace hvx::app
