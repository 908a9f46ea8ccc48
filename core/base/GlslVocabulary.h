#pragma once
// The GLSL vocabulary in C++: the types and built-in functions that core/*/*.glsl uses,
// taken from GLM into hvx::core::glsl, so that those sources compile as C++ too (decision 2 of
// DESIGN.md). Included by the headers that compile a shared source.
#include <cstdint>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace hvx::core::glsl {
using uint = std::uint32_t;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using mat3 = glm::mat3;
using glm::abs;
using glm::clamp;
using glm::dot;
using glm::exp;
using glm::floor;
using glm::length;
using glm::max;
using glm::min;
using glm::mix;
using glm::normalize;
using glm::reflect;
using glm::refract;
using glm::pow;
using glm::sqrt;
using glm::step;
using glm::transpose;
}  // namespace hvx::core::glsl
