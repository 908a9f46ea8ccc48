#pragma once
// The small ray arithmetic the CPU ray casters share with the shader (raycast_march.glsl's
// rayInverse and brick_sampling.glsl's cellVisible): a ray's inverse direction for slab tests,
// and the 4×4×4 cell of a leaf (core::BrickCells) a point lies in and where the ray leaves it.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace hvx::core::ray_cells {

/// 1 / d per axis, ±1e30 along an axis the ray (nearly) parallels.
inline glm::vec3 inverse(const glm::vec3& d) {
    glm::vec3 inv;
    for (int a = 0; a < 3; ++a) inv[a] = std::abs(d[a]) > 1e-20f ? 1.0f / d[a] : (d[a] >= 0 ? 1e30f : -1e30f);
    return inv;
}

/// The cell (of BrickCells' 4×4×4) of a leaf with corner `lo` and cell size `cell` holding p.
inline glm::ivec3 index(const glm::vec3& p, const glm::vec3& lo, float cell) {
    return glm::clamp(glm::ivec3(glm::floor((p - lo) / cell)), glm::ivec3(0), glm::ivec3(3));
}

/// Whether a cell may show under a brick's visible-cell bits.
inline bool visible(std::uint64_t bits, const glm::ivec3& c) { return ((bits >> (c.x + 4 * c.y + 16 * c.z)) & 1u) != 0; }

/// The parameter where the ray o + t·d (inv = inverse(d)) leaves cell c of the leaf at `lo`.
inline float exit(const glm::ivec3& c, const glm::vec3& lo, float cell, const glm::vec3& o, const glm::vec3& inv) {
    const glm::vec3 cellLo = lo + glm::vec3(c) * cell;
    const glm::vec3 far = glm::max((cellLo - o) * inv, (cellLo + cell - o) * inv);
    return std::min(std::min(far.x, far.y), far.z);
}

}  // namespace hvx::core::ray_cells
