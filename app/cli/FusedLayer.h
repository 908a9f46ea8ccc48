#pragma once
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "app/cli/CliArgs.h"
#include "core/appearance/TransferFunction.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/WorkingSet.h"

namespace hvx::app {

/// The second volume of `render` and `lightfield --overlay/--labels`, fused in the same ray
/// march: its reader, transfer function (a colour map over a window, or a label table) and
/// working set (the base volume's options, without its crop and clip; culled by its own
/// transfer function). Throws core::Error for a partner that cannot be fused, in a sentence.
struct FusedLayer {
    std::string path, description;
    std::unique_ptr<core::OctreeReader> reader;
    std::unique_ptr<core::TransferFunction> tf;
    core::BrickCache cache;
    core::BrickLoader loader;
    core::WorkingSet ws;

    /// `spec`: "B.hvo[:lut=NAME,opacity=O,window=W/L]" (an overlay) or a label map's path
    /// (`labels`); `args` gives --lut, --label-opacity and --force-frame, its first positional
    /// argument the base volume's name.
    FusedLayer(const std::string& spec, bool labels, const CliArgs& args, const core::VolumeGeometry& base,
               std::size_t cacheBytes, const core::WorkingSetOptions& baseOptions);

private:
    FusedLayer(std::pair<std::string, std::map<std::string, std::string>> parsed, bool labels, const CliArgs& args,
               const core::VolumeGeometry& base, std::size_t cacheBytes, const core::WorkingSetOptions& baseOptions);
    std::unique_ptr<core::TransferFunction> makeTf(const std::map<std::string, std::string>& opts, bool labels,
                                                   const CliArgs& args, const core::VolumeGeometry& base);
    static core::WorkingSetOptions options(core::WorkingSetOptions o);
};

}  // namespace hvx::app
