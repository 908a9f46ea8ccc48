#pragma once
#include <QString>

#include <utility>
#include <vector>

#include "core/appearance/TransferFunctionSpec.h"

namespace hvx::ui {

/// Reading and writing transfer functions: Holovox's own JSON (physical units, so it carries
/// across volumes with different rescale), 3D Slicer VolumeProperty presets (`presets.xml`,
/// physical units) and ParaView colour-map JSON (rescaled to the volume's range, as ParaView
/// applies presets). Specs in and out of these functions are in physical units; every reader
/// throws core::Error naming the file and what is wrong.
///
/// Threading: free functions, any thread.
class TransferFunctionFiles {
public:
    static void save(const core::TransferFunctionSpec& physical, const QString& path);
    static core::TransferFunctionSpec load(const QString& path);
    /// Every VolumeProperty of a Slicer presets file, by name.
    static std::vector<std::pair<QString, core::TransferFunctionSpec>> readSlicerPresets(const QString& path);
    /// The first colour map of a ParaView JSON file, its points spread over [lo, hi]. Maps
    /// without opacity points keep `opacity` from `current`.
    static core::TransferFunctionSpec readParaView(const QString& path, double lo, double hi,
                                                   const core::TransferFunctionSpec& current);
    /// Physical <-> stored units of a spec (stored = (physical - intercept) / slope).
    static core::TransferFunctionSpec toStored(core::TransferFunctionSpec s, double slope, double intercept);
    static core::TransferFunctionSpec toPhysical(core::TransferFunctionSpec s, double slope, double intercept);
};

}  // namespace hvx::ui
