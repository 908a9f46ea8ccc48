#pragma once
// C++ side of core/appearance/Enhancers.glsl: the same source compiled with GLM types, so the CPU
// reference applies exactly the enhancers the shader does.
#include "core/base/GlslVocabulary.h"

namespace hvx::core::glsl {
#define HVX_INOUT(T) T&
#define HVX_FN inline
#define HVX_TOOL_ON(bit) ((hvxBits & (bit)) != 0)
#include "core/appearance/Enhancers.glsl"
#undef HVX_INOUT
#undef HVX_FN
#undef HVX_TOOL_ON
}  // namespace hvx::core::glsl

#include "core/appearance/ToolSet.h"

namespace hvx::core {
/// The shader's tool block from a ToolSet (shading: the frame's Phong parameters).
glsl::HvxTools packTools(const ToolSet& tools, const glm::dvec4& shading);
}  // namespace hvx::core
