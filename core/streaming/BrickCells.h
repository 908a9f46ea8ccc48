#pragma once
#include <array>
#include <cstdint>

#include <glm/vec2.hpp>

#include "core/octree/Brick.h"

namespace hvx::core {

class TransferFunction;

/// Value ranges of a brick's 4×4×4 cells, for empty-space skipping inside a brick (the index
/// skips whole bricks; a brick on the edge of an object is mostly background). Cell (i, j, k)
/// spans the interior voxels [i·n/4, (i+1)·n/4) per axis, n the brick size; its range covers
/// every value trilinear interpolation can return anywhere in the cell's box, that is one
/// more sample on each side, taken from the brick's border.
struct BrickCells {
    static constexpr int kPerAxis = 4;
    static constexpr int kCount = kPerAxis * kPerAxis * kPerAxis;
    /// (min, max) in stored units, cell i + 4·j + 16·k.
    std::array<glm::vec2, kCount> ranges{};

    /// The ranges of a decoded brick with `brickSize` interior samples and `border` (≥ 1) per
    /// side. Throws core::Error when the size is not a multiple of 4 or there is no border.
    static BrickCells of(const Brick& brick, std::uint32_t brickSize, std::uint32_t border);
    /// The same for a brick already decoded to floats ((brickSize + 2·border)^3 samples, x
    /// fastest), as the CPU reference holds them.
    static BrickCells ofSamples(const float* samples, std::uint32_t brickSize, std::uint32_t border);

    /// The ranges of a split-voxel brick (brickSize³ cells, no border): the front and back
    /// values of the split-voxels in each block of (brickSize/4)³ (a split-voxel is constant on
    /// either side of its plane, so nothing beyond the block is read). A brick size not
    /// divisible by 4 gives unbounded ranges (every block may show).
    static BrickCells ofSplit(const Brick& brick);

    /// Bit c set where cell c may show under `tf`: its range, widened by one table entry each
    /// side (the table is interpolated between entries), meets non-zero opacity. `exact`: the
    /// values are classified by their own entry (a split-voxel label map's), never widened.
    std::uint64_t visible(const TransferFunction& tf, bool exact = false) const;
    /// Bit c set where cell c may hold the iso surface of `value` (min <= value <= max): in
    /// any other cell, all samples lie on one side of the value.
    std::uint64_t straddling(double value) const;
};

}  // namespace hvx::core
