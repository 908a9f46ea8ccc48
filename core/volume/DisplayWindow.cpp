#include "core/volume/DisplayWindow.h"

#include <algorithm>

#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

const std::vector<DisplayWindow>& DisplayWindow::ctPresets() {
    static const std::vector<DisplayWindow> presets = {
        {"brain", 40, 80},       {"subdural", 75, 215},    {"stroke", 40, 40},    {"bone", 400, 1800},
        {"lung", -600, 1500},    {"mediastinum", 50, 350}, {"abdomen", 50, 400},  {"liver", 30, 150},
    };
    return presets;
}

DisplayWindow DisplayWindow::initial(const VolumeGeometry& g, std::optional<std::pair<double, double>> percentiles) {
    if (!g.windows.empty()) return g.windows.front();
    if (g.hounsfield()) return {"CT default", 40, 400};
    if (percentiles && percentiles->second > percentiles->first)
        return {"1st-99th percentile", 0.5 * (percentiles->first + percentiles->second),
                percentiles->second - percentiles->first};
    const double a = g.valueMin * g.rescaleSlope + g.rescaleIntercept, b = g.valueMax * g.rescaleSlope + g.rescaleIntercept;
    const double lo = std::min(a, b), hi = std::max(a, b);
    return {"full range", 0.5 * (lo + hi), std::max(1e-6, hi - lo)};
}

std::vector<DisplayWindow> DisplayWindow::presetsFor(const VolumeGeometry& g) {
    std::vector<DisplayWindow> out = g.windows;
    if (g.hounsfield()) out.insert(out.end(), ctPresets().begin(), ctPresets().end());
    return out;
}

}  // namespace hvx::core
