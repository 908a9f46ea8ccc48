#include "core/camera/InteractiveQuality.h"

#include <algorithm>
#include <cmath>

namespace hvx::core {

InteractiveQuality::Level InteractiveQuality::next(bool moving) const {
    if (!moving) return {};
    Level level;
    level.stepScale = options_.movingStepScale;
    level.subFrame = options_.subFrames;
    // Work scales with pixels (resolution^2, a quarter of them in a sub-frame) and samples per
    // ray (1 / step).
    if (fullFrameMs_ > 0.0) {
        const double fraction = options_.targetFrameMs * level.stepScale * (level.subFrame ? 4.0 : 1.0) / fullFrameMs_;
        level.resolution = std::clamp(std::sqrt(fraction), options_.minResolution, 1.0);
    } else {
        level.resolution = 0.5;  // nothing measured yet: a safe first guess
    }
    return level;
}

void InteractiveQuality::frameDone(const Level& used, double ms) {
    if (!(ms > 0.0)) return;
    const double work = used.resolution * used.resolution / used.stepScale * (used.subFrame ? 0.25 : 1.0);
    const double estimate = ms / work;
    // Smoothed, so one slow frame (a shader compile, a burst of uploads) does not swing the size.
    fullFrameMs_ = fullFrameMs_ > 0.0 ? 0.7 * fullFrameMs_ + 0.3 * estimate : estimate;
}

}  // namespace hvx::core
