#pragma once
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/appearance/Enhancers.h"
#include "core/reference/RenderSettings.h"

namespace hvx::core {

/// A tool sample's colour after the enhancers (raycast_march.glsl's toolColour, in its float
/// operations): Phong by its gradient (none: facing the viewer) mixed by x.lit with ambient +
/// emission where a tool emphasises it; a sample already shaded (x.lit < 0) keeps its colour.
inline glm::vec3 toolColour(const glsl::HvxSample& x, const RenderSettings& s) {
    if (x.lit < 0.0f) return x.c;
    const float gl2 = glm::dot(x.g, x.g);
    const float ndl = gl2 > 0.0f ? std::abs(glm::dot(x.g, -x.v)) / std::sqrt(gl2) : 1.0f;
    const glm::vec3 phong = s.shading ? x.c * float(s.ambient + s.diffuse * ndl) + glm::vec3(float(s.specular) * std::pow(ndl, float(s.shininess)))
                                      : x.c;
    return glm::mix(x.c * float(s.ambient + kEmphasisEmission), phong, x.lit);
}

}  // namespace hvx::core
