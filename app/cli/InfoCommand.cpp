#include <cstdio>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "core/base/Error.h"
#include "core/octree/OctreeReader.h"
#include "core/octree/OctreeSummary.h"

namespace hvx::app {

int infoCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {}, {"verify"});
    if (args.positional().size() != 1) throw core::Error("usage: holovox-cli info FILE.hvo [--verify]");
    const auto reader = core::OctreeReader::open(args.positional()[0], true);  // split-voxel octrees too
    std::fputs(core::OctreeSummary::of(*reader).format(*reader).c_str(), stdout);
    if (args.flag("verify")) {
        // Reads and checks every payload; the first corrupt brick ends with an error naming it.
        for (std::uint32_t n = 0; n < reader->nodes().size(); ++n) reader->readBrick(n);
        std::printf("  verified    all %zu bricks read back with matching checksums\n", reader->nodes().size());
    }
    return 0;
}

}  // namespace hvx::app
