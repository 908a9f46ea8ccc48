#pragma once
// C++ side of core/streaming/IndexTraversal.glsl: the same source compiled with GLM types, so the
// CPU reference ray caster walks the index exactly as the shader does.
#include "core/base/GlslVocabulary.h"
#include "core/streaming/SpatialIndex.h"

namespace hvx::core::glsl {
#define HVX_INDEX_PARAM const ::hvx::core::SpatialIndex& hvxIndex
#define HVX_INDEX_ARG hvxIndex
#define HVX_NODE(i) hvxIndex.nodes[(i)]
#define HVX_ROPE(i, f) hvxIndex.ropes[std::size_t(i) * 6u + std::size_t(f)]
#define HVX_INOUT(T) T&
#define HVX_FN inline
#include "core/streaming/IndexTraversal.glsl"
#undef HVX_INDEX_PARAM
#undef HVX_INDEX_ARG
#undef HVX_NODE
#undef HVX_ROPE
#undef HVX_INOUT
#undef HVX_FN
}  // namespace hvx::core::glsl
