#pragma once
#include <vector>

#include "core/image/RenderImage.h"
#include "core/camera/DisplayModel.h"

namespace hvx::core {

/// What an observer sees on a horizontal-parallax projector display: for each screen point, the
/// beam of the projector whose ray through that point passes closest (horizontally) to the
/// observer, if within the beam angle; the screen scatters vertically, so height does not select.
/// Each projector image covers the screen rectangle. Used for the GUI preview and the tests.
///
/// Threading: a pure function.
class LightFieldSimulator {
public:
    /// `projectorImages` in projector order; `observer` in display coordinates (mm).
    static RenderImage observe(const DisplayModel& display, const std::vector<RenderImage>& projectorImages,
                               const glm::dvec3& observer);
};

}  // namespace hvx::core
