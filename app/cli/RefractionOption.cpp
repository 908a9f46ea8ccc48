#include "app/cli/RefractionOption.h"

#include "core/base/Error.h"

namespace hvx::app {

void applyRefractionOption(const CliArgs& args, const core::VolumeGeometry& g, const std::string& refusal,
                           core::TransferFunction& tf) {
    const auto refraction = args.value("refraction");
    if (!refraction) return;
    if (!refusal.empty()) throw core::Error(refusal);
    if (refraction->find(':') == std::string::npos) {
        tf.setRefraction(tf.refractionByOpacity(CliArgs::numbers(*refraction, 1, "--refraction")[0]));
        return;
    }
    std::vector<core::TransferFunction::RefractionPoint> points;
    for (const auto& [v, index] : CliArgs::pairs(*refraction, "--refraction", "VALUE:INDEX", "-1000:1,0:1.33"))
        points.push_back({(v - g.rescaleIntercept) / g.rescaleSlope, index});
    tf.setRefraction(std::move(points));
}

}  // namespace hvx::app
