#pragma once
#include <functional>

#include <glm/vec3.hpp>

#include "core/camera/View.h"

namespace hvx::core {

/// The largest voxel (mm) a view accepts at a point. The default is `voxelsPerPixel` times the
/// pixel footprint (1 voxel per pixel); a light-field display plugs in s(z) = s0 + 2|z|tan(phi/2).
using AccuracyFunction = std::function<double(const View& view, const glm::dvec3& point)>;

}  // namespace hvx::core
