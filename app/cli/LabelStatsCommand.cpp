#include <cstdio>
#include <fstream>
#include <optional>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "core/base/AtomicFileWriter.h"
#include "core/base/Error.h"
#include "core/base/JobContext.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/LabelStatistics.h"
#include "core/volume/FramePairing.h"

namespace hvx::app {

int labelStatsCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"lut", "o", "output"}, {"force-frame"});
    if (args.positional().size() != 2)
        throw core::Error("usage: holovox-cli label-stats IMAGE.hvo LABELS.hvo [--lut FILE] [--force-frame] [-o OUT.csv]");
    const auto image = core::OctreeReader::open(args.positional()[0]);
    const auto labels = core::OctreeReader::open(args.positional()[1]);
    const auto pairing = core::FramePairing::of(image->geometry(), args.positional()[0], labels->geometry(),
                                                args.positional()[1]);
    if (pairing.refused && !args.flag("force-frame"))
        throw core::Error(pairing.sentence + " (--force-frame measures anyway)");
    if (!pairing.sentence.empty()) std::fprintf(stderr, "note: %s\n", pairing.sentence.c_str());
    std::optional<core::LabelTable> table;
    const std::string sidecar = core::LabelTable::sidecarPath(args.positional()[1]);
    if (const auto lut = args.value("lut")) table = core::LabelTable::load(*lut);
    else if (std::ifstream(sidecar)) table = core::LabelTable::load(sidecar);
    core::JobContext job;
    const auto stats = core::LabelStatistics::compute(*image, *labels, job);
    const std::string csv = stats.csv(table ? &*table : nullptr);
    const auto out = args.value("o") ? args.value("o") : args.value("output");
    if (out) {
        core::AtomicFileWriter w(*out);
        w.append(csv.data(), csv.size());
        w.commit();
        std::fprintf(stderr, "wrote %s (%zu labels)\n", out->c_str(), stats.rows.size());
    } else {
        std::fputs(csv.c_str(), stdout);
    }
    if (!stats.note.empty()) std::fprintf(stderr, "note: %s\n", stats.note.c_str());
    return 0;
}

}  // namespace hvx::app
