#include "app/cli/FusedLayer.h"

#include <cstdio>

#include "app/cli/OverlayOptions.h"
#include "core/appearance/LabelTable.h"
#include "core/base/Error.h"
#include "core/streaming/OctreeSpace.h"

namespace hvx::app {

FusedLayer::FusedLayer(const std::string& spec, bool labels, const CliArgs& args, const core::VolumeGeometry& base,
                       std::size_t cacheBytes, const core::WorkingSetOptions& baseOptions)
    : FusedLayer(labels ? std::make_pair(spec, std::map<std::string, std::string>{}) : overlaySpec(spec), labels, args, base,
                 cacheBytes, baseOptions) {}

FusedLayer::FusedLayer(std::pair<std::string, std::map<std::string, std::string>> parsed, bool labels, const CliArgs& args,
                       const core::VolumeGeometry& base, std::size_t cacheBytes, const core::WorkingSetOptions& baseOptions)
    : path(parsed.first), reader(core::OctreeReader::open(path)), tf(makeTf(parsed.second, labels, args, base)),
      cache(cacheBytes), loader(*reader, cache), ws(*reader, cache, loader, options(baseOptions)) {}

std::unique_ptr<core::TransferFunction> FusedLayer::makeTf(const std::map<std::string, std::string>& opts, bool labels,
                                                           const CliArgs& args, const core::VolumeGeometry& base) {
    const auto& g = reader->geometry();
    pairFrames(base, args.positional()[0], g, path, args.flag("force-frame"));
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    if (labels) {
        if (!g.isLabel) throw core::Error(path + " is not a label map (build it with --labels); --overlay lays an image over");
        const auto table = core::LabelTable::forLabelMap(path, g.valueMin, g.valueMax, args.value("lut").value_or(""));
        const double opacity = args.number("label-opacity").value_or(1.0);
        if (!(opacity >= 0 && opacity <= 1)) throw core::Error("--label-opacity must be 0 to 1");
        description = "labels, " + table.format();
        return std::make_unique<core::TransferFunction>(core::TransferFunction::forLabels(table, opacity, space.minSpacing));
    }
    if (g.isLabel) throw core::Error(path + " is a label map: lay it over with --labels");
    const auto look = overlayLook(opts, g);
    // The window is in physical units; the transfer function runs over stored values.
    const double lo = (look.window.centre - look.window.width / 2 - g.rescaleIntercept) / g.rescaleSlope;
    const double hi = (look.window.centre + look.window.width / 2 - g.rescaleIntercept) / g.rescaleSlope;
    char text[160];
    std::snprintf(text, sizeof text, "%s map, window W %.6g / L %.6g, opacity %.2g", look.map.name().c_str(),
                  look.window.width, look.window.centre, look.opacity);
    description = text;
    return std::make_unique<core::TransferFunction>(
        core::TransferFunction::forColorMap(look.map, lo, hi, look.opacity, g.valueMin, g.valueMax, space.minSpacing));
}

core::WorkingSetOptions FusedLayer::options(core::WorkingSetOptions o) {
    o.crop = {};  // the overlay is cut by the base volume's box, not by its crop
    o.clip = false;
    o.cullByTransferFunction = true;
    return o;
}

}  // namespace hvx::app
