#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/octree/SplitVoxel.h"
#include "core/volume/ScalarType.h"

namespace hvx::core {

/// One decoded brick: edge^3 samples, x fastest, border included. Lossy nodes come back as
/// uint8 codes with the range they stand for; empty nodes come back as a constant brick at the
/// node's minimum with `empty` set.
struct Brick {
    std::uint32_t node = 0;
    std::uint32_t edge = 0;
    ScalarType type = ScalarType::UInt8;
    bool empty = false;
    bool lossy8 = false;
    float quantMin = 0.0f;  ///< lossy8: value of code 0
    float quantMax = 0.0f;  ///< lossy8: value of code 255
    bool splitVoxels = false;  ///< a split-voxel octree's brick: edge³ encoded cells, not samples
    std::vector<std::byte> data;

    template <class T>
    const T* as() const { return reinterpret_cast<const T*>(data.data()); }
    /// Stored (not rescaled) value of sample (x, y, z), decoding lossy codes.
    double value(std::uint32_t x, std::uint32_t y, std::uint32_t z) const;
    /// Split-voxel bricks: cell (x, y, z), decoded.
    SplitVoxel cell(std::uint32_t x, std::uint32_t y, std::uint32_t z) const;
};

}  // namespace hvx::core
