#pragma once
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/appearance/TransferFunction.h"
#include "core/image/RenderImage.h"
#include "tests/support/MemoryVoxelSource.h"

namespace hvx::test {

/// The angle between two directions, in degrees.
inline double degreesBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)));
}

/// 128³: a sphere (radius 44 voxels) cut by an oblique plane into 100 and 200, in air (0).
inline DenseVolume twoMaterialSphere() {
    DenseVolume v;
    v.dims = {128, 128, 128};
    const glm::dvec3 c(63.5, 63.5, 63.5), n = glm::normalize(glm::dvec3(1.0, 0.3, 0.2));
    for (std::uint32_t k = 0; k < 128; ++k)
        for (std::uint32_t j = 0; j < 128; ++j)
            for (std::uint32_t i = 0; i < 128; ++i) {
                const glm::dvec3 p(i, j, k);
                v.values.push_back(glm::length(p - c) > 44.0 ? 0.0 : glm::dot(n, p - c) >= 0 ? 200.0 : 100.0);
            }
    return v;
}

/// Red at 100, green at 200, and blue at 150, which no voxel of twoMaterialSphere holds: blue
/// can only come from a value made between the two materials.
inline core::TransferFunction threeColours() {
    using P = core::TransferFunction::Point;
    return core::TransferFunction({P{0, {0, 0, 0, 0}}, P{80, {1, 0, 0, 0}}, P{100, {1, 0, 0, 0.9}}, P{120, {1, 0, 0, 0}},
                                   P{135, {0, 0, 1, 0}}, P{150, {0, 0, 1, 0.9}}, P{165, {0, 0, 1, 0}}, P{180, {0, 1, 0, 0}},
                                   P{200, {0, 1, 0, 0.9}}, P{255, {0, 1, 0, 0.9}}},
                                  0.0, 255.0, 1.0);
}

/// Pixels of a colour neither material of twoMaterialSphere has under threeColours (blue).
inline int foreignPixels(const core::RenderImage& img) {
    int n = 0;
    for (const auto& p : img.rgba) n += p.b > 0.02f;
    return n;
}

}  // namespace hvx::test
