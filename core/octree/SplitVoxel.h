#pragma once
#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>

namespace hvx::core {

/// The split-voxel primitive (thesis §4.3, Fig. 4.2): one cell that stands for a block of
/// N³ voxels with two constant values, front F and back B, and the oriented feature plane
/// between them. Coordinates are the cell's own, [0, 1]³; the plane is
/// dot(normal, x - (0.5, 0.5, 0.5)) = offset, the normal points from the back material into
/// the front one. A uniform cell has F = B and a zero normal (the thesis's null plane).
///
/// Encoding (§4.4.1.3): the plane in 4 bytes (normal components and offset as signed bytes,
/// the offset in units of half the cell's diagonal), F and B in one byte each for 8-bit data
/// (6 bytes) or two bytes each for 16-bit data (8 bytes), the stored values' own bits.
struct SplitVoxel {
    float front = 0.0f;
    float back = 0.0f;
    glm::vec3 normal{0.0f};
    float offset = 0.0f;

    /// A uniform cell of one value.
    static SplitVoxel uniform(float value) { return {value, value, glm::vec3(0.0f), 0.0f}; }
    bool isUniform() const { return normal == glm::vec3(0.0f); }
    /// The value at a point of the cell (cell coordinates): F on the plane's front side, B behind.
    float valueAt(const glm::vec3& p) const;
    /// The fraction of the cell on the plane's front side (1 for a uniform cell), estimated on
    /// a 4³ grid of points as the hierarchy's resampling does.
    float frontFraction() const;

    /// Bytes of one encoded split-voxel for stored values of `valueBytes` bytes (1 or 2).
    static std::size_t encodedSize(std::size_t valueBytes) { return 4 + 2 * valueBytes; }
    /// Writes the encoding to `out` (encodedSize bytes). Values are the stored values, integers
    /// of the type (`isSigned`, `valueBytes`); the plane is quantised as said above.
    void encode(std::uint8_t* out, std::size_t valueBytes, bool isSigned) const;
    static SplitVoxel decode(const std::uint8_t* in, std::size_t valueBytes, bool isSigned);
    /// Largest offset the encoding keeps: half the cell's diagonal (a plane farther from the
    /// centre misses the cell, which is then uniform).
    static constexpr float kMaxOffset = 0.8660254f;
};

}  // namespace hvx::core
