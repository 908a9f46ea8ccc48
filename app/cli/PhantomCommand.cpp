#include <cstdio>
#include <filesystem>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "app/cli/OctreeBuildRunner.h"
#include "app/cli/ProgressBar.h"
#include "app/cli/SignalCancel.h"
#include "core/base/Error.h"
#include "core/volume/NrrdWriter.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"

namespace hvx::app {

int phantomCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"size", "o", "output", "seed", "brick", "noise"}, {"quiet"});
    const auto size = args.value("size");
    const auto out = args.value("o") ? args.value("o") : args.value("output");
    if (!size || !out || !args.positional().empty())
        throw core::Error("usage: holovox-cli phantom --size XxYxZ -o OUT.{nrrd,hvo} [--seed N]");
    const auto dims = core::VoxelSourceFactory::parseDims(*size);
    const auto seed = std::uint64_t(args.integer("seed", 1, 0, 1L << 62));
    const double noise = args.number("noise").value_or(15.0);
    core::PhantomVoxelSource phantom(dims, seed, {500.0, 500.0, 500.0}, noise);
    const std::string ext = std::filesystem::path(*out).extension().string();
    if (ext == ".hvo") {
        core::BuildOptions opt;
        opt.brickSize = std::uint32_t(args.integer("brick", 32, 4, 256));
        OctreeBuildRunner::run(phantom, *out, opt, !args.flag("quiet"));
    } else if (ext == ".nrrd") {
        ProgressBar bar("phantom");
        core::JobContext job(bar.observer());
        SignalCancel cancelOnSignal(job);
        core::NrrdWriter::write(phantom, *out, job);
        bar.finish();
        std::printf("wrote %s (%s)\n", out->c_str(), phantom.describe().c_str());
    } else {
        throw core::Error(*out + ": output must end in .nrrd or .hvo");
    }
    return 0;
}

}  // namespace hvx::app
