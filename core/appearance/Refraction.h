#pragma once
// C++ side of core/appearance/Refraction.glsl: the same source compiled with GLM types, so that
// the CPU reference bends its rays exactly as the shader does.
#include "core/base/GlslVocabulary.h"

namespace hvx::core::glsl {
#define HVX_FN inline
#include "core/appearance/Refraction.glsl"
#undef HVX_FN
}  // namespace hvx::core::glsl
