#pragma once
// C++ side of core/shared/Enhancers.glsl: the same source compiled with GLM types, so the CPU
// reference applies exactly the enhancers the shader does.
#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace hvx::core::glsl {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using mat3 = glm::mat3;
using glm::length;
using glm::transpose;
using glm::abs;
using glm::clamp;
using glm::dot;
using glm::exp;
using glm::max;
using glm::min;
using glm::mix;
using glm::pow;
using glm::sqrt;

#define HVX_INOUT(T) T&
#define HVX_FN inline
#define HVX_TOOL_ON(bit) ((hvxBits & (bit)) != 0)
#include "core/shared/Enhancers.glsl"
#undef HVX_INOUT
#undef HVX_FN
#undef HVX_TOOL_ON
}  // namespace hvx::core::glsl

#include "core/ToolSet.h"

namespace hvx::core {
/// The shader's tool block from a ToolSet (shading: the frame's Phong parameters).
glsl::HvxTools packTools(const ToolSet& tools, const glm::dvec4& shading);
}  // namespace hvx::core
