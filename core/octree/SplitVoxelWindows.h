#pragma once
#include <algorithm>
#include <array>
#include <cstdint>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "core/octree/SplitVoxel.h"

namespace hvx::core::split {

using Dims = std::array<std::uint32_t, 3>;

/// The window of level-0 cell (x, y, z): its N³ voxels and M layers around them, x fastest,
/// (N + 2M)³ values; voxels beyond the volume (of `dims`) replicate its faces, as brick
/// borders do. `voxel(i, j, k)` returns a voxel's stored value (indices inside the volume).
template <class Voxel>
void fillVoxelWindow(const Voxel& voxel, const Dims& dims, std::uint32_t N, std::uint32_t M, std::uint32_t x,
                     std::uint32_t y, std::uint32_t z, float* w) {
    const std::uint32_t E = N + 2 * M;
    const auto clampTo = [](long v, std::uint32_t size) { return std::uint32_t(std::clamp(v, 0L, long(size) - 1)); };
    for (std::uint32_t k = 0; k < E; ++k) {
        const std::uint32_t kk = clampTo(long(z * N + k) - long(M), dims[2]);
        for (std::uint32_t j = 0; j < E; ++j) {
            const std::uint32_t jj = clampTo(long(y * N + j) - long(M), dims[1]);
            for (std::uint32_t i = 0; i < E; ++i) *w++ = voxel(clampTo(long(x * N + i) - long(M), dims[0]), jj, kk);
        }
    }
}

/// Samples per finer cell edge when a coarser level is fitted (§4.4.2), and the window's
/// interior and overlap in those samples.
constexpr std::uint32_t kResample = 2;
inline std::uint32_t coarseInterior() { return 2 * kResample; }
inline std::uint32_t coarseOverlap(std::uint32_t overlap) { return overlap * kResample; }

/// The window of coarser cell (x, y, z): the finer level (of `fineDims` cells) resampled at
/// kResample³ points per finer cell, each point the value of its side of that cell's plane,
/// over the coarser cell's 2³ finer cells and `overlap` finer cells around them (clamped to
/// the finer grid). `cell(x, y, z)` returns a finer SplitVoxel.
template <class Cell>
void fillCellWindow(const Cell& cell, const Dims& fineDims, std::uint32_t overlap, std::uint32_t x, std::uint32_t y,
                    std::uint32_t z, float* w) {
    const std::uint32_t M = coarseOverlap(overlap), E = coarseInterior() + 2 * M;
    const glm::dvec3 last = glm::dvec3(fineDims[0], fineDims[1], fineDims[2]) - 1e-6;
    for (std::uint32_t k = 0; k < E; ++k)
        for (std::uint32_t j = 0; j < E; ++j)
            for (std::uint32_t i = 0; i < E; ++i) {
                // Sample (i, j, k)'s position in finer cells, clamped to the finer grid.
                const glm::dvec3 fine = glm::dvec3(2.0 * x, 2.0 * y, 2.0 * z) + (glm::dvec3(i, j, k) - double(M) + 0.5) / double(kResample);
                const glm::dvec3 c = glm::clamp(fine, glm::dvec3(0.0), last);
                const glm::uvec3 at(c);
                *w++ = cell(at.x, at.y, at.z).valueAt(glm::vec3(c - glm::dvec3(at)));
            }
}

/// The finer cell rows (along z) a coarser row `z` reads: [first, last], inside the grid.
inline std::array<std::uint32_t, 2> finerRows(std::uint32_t z, std::uint32_t overlap, std::uint32_t fineRows) {
    const long lo = 2L * z - long(overlap), hi = 2L * z + 1 + long(overlap);
    return {std::uint32_t(std::clamp(lo, 0L, long(fineRows) - 1)), std::uint32_t(std::clamp(hi, 0L, long(fineRows) - 1))};
}

}  // namespace hvx::core::split
