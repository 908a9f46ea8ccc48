#include "ui/ToolDragger.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/trigonometric.hpp>

namespace hvx::ui {

void ToolDragger::press(const QPoint& pos) {
    active_ = true;
    moved_ = false;
    pressPos_ = pos;
}

std::optional<core::ToolSet> ToolDragger::move(const QPoint& pos, const QPoint& delta, bool shift,
                                               const core::ToolSet& tools, const core::OrbitCamera& camera, int width,
                                               int height) {
    if ((pos - pressPos_).manhattanLength() > 3) moved_ = true;
    if (!moved_) return std::nullopt;
    if (tools.focal.enabled || tools.context.enabled) return movedProbes(tools, delta, shift, camera, width, height);
    if (tools.clip.enabled) return movedClipPlane(tools, delta, shift, camera, height);
    return std::nullopt;
}

bool ToolDragger::release() {
    const bool click = active_ && !moved_;
    active_ = false;
    return click;
}

std::optional<core::ToolSet> ToolDragger::scaled(const core::ToolSet& tools, double steps) {
    if (!tools.focal.enabled && !tools.context.enabled) return std::nullopt;
    core::ToolSet t = tools;
    const double f = std::pow(1.1, steps);
    t.focal.radii = glm::clamp(t.focal.radii * f, glm::dvec3(1.0), glm::dvec3(2000.0));
    t.context.radius = std::clamp(t.context.radius * f, 1.0, 2000.0);
    return t;
}

core::ToolSet ToolDragger::movedProbes(core::ToolSet tools, const QPoint& d, bool alongView,
                                       const core::OrbitCamera& camera, int width, int height) {
    // One pixel's millimetres at the probe's depth, so the probe follows the cursor.
    const glm::dvec3 centre = tools.focal.enabled ? tools.focal.centre : tools.context.centre;
    const double depth = -glm::dot(centre - camera.view(width, height).eye, camera.back());
    const double mmPerPixel = 2.0 * depth * std::tan(glm::radians(camera.fovYDegrees()) / 2.0) / std::max(1, height);
    const glm::dvec3 delta = alongView ? -camera.back() * (-d.y() * mmPerPixel)
                                       : (camera.right() * double(d.x()) - camera.up() * double(d.y())) * mmPerPixel;
    tools.focal.centre += delta;
    tools.context.centre += delta;
    return tools;
}

core::ToolSet ToolDragger::movedClipPlane(core::ToolSet tools, const QPoint& d, bool tilt,
                                          const core::OrbitCamera& camera, int height) {
    glm::dvec3 n = glm::normalize(tools.clip.normal);
    // A point of the plane, kept fixed while tilting: the projection of the camera's target.
    const glm::dvec3 onPlane = camera.target() - n * (glm::dot(n, camera.target()) + tools.clip.offset);
    if (tilt) {  // turn the plane about the view's axes through that point
        const double perPixel = glm::pi<double>() / std::max(1, height);
        n = glm::angleAxis(d.x() * perPixel, camera.up()) * (glm::angleAxis(d.y() * perPixel, camera.right()) * n);
        tools.clip.normal = n;
        tools.clip.offset = -glm::dot(n, onPlane);
    } else {  // push the plane along its normal, one pixel's millimetres per pixel
        const double mmPerPixel =
            2.0 * camera.distance() * std::tan(glm::radians(camera.fovYDegrees()) / 2.0) / std::max(1, height);
        tools.clip.normal = n;
        tools.clip.offset = tools.clip.offset - d.y() * mmPerPixel;
    }
    return tools;
}

}  // namespace hvx::ui
