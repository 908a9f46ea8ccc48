#pragma once
#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace hvx::core {

/// What is kept of a volume when it is cropped: a box whose faces are parallel to the volume's
/// voxel grid (as Slicer's ROI fitted to a volume), given as fractions (0..1) of the volume's
/// extent along its own index axes i, j, k. The whole volume is min 0, max 1. What the box
/// removes is neither drawn nor refined nor loaded.
struct CropBox {
    glm::dvec3 min{0.0}, max{1.0};

    /// True when nothing is cropped.
    bool whole() const { return min == glm::dvec3(0.0) && max == glm::dvec3(1.0); }
    /// A box from millimetres measured from the volume's first corner along i, j, k (a volume
    /// of `dims` voxels of `spacing` mm). Faces beyond the volume are clamped to it; a box
    /// turned inside out or thinner than a voxel along an axis throws core::Error saying which.
    static CropBox fromMillimetres(const glm::dvec3& lowMm, const glm::dvec3& highMm,
                                   const std::array<std::uint32_t, 3>& dims, const glm::dvec3& spacing);
    /// The box's faces in millimetres from the first corner (the inverse of fromMillimetres).
    std::array<glm::dvec3, 2> millimetres(const std::array<std::uint32_t, 3>& dims, const glm::dvec3& spacing) const;
};

}  // namespace hvx::core
