#include "core/volume/CropBox.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/base/Error.h"

namespace hvx::core {

CropBox CropBox::fromMillimetres(const glm::dvec3& lowMm, const glm::dvec3& highMm,
                                 const std::array<std::uint32_t, 3>& dims, const glm::dvec3& spacing) {
    static const char* axis[3] = {"i", "j", "k"};
    CropBox b;
    for (int a = 0; a < 3; ++a) {
        const double length = double(dims[std::size_t(a)]) * spacing[a];
        if (!std::isfinite(lowMm[a]) || !std::isfinite(highMm[a]))
            throw Error(std::string("the crop box's ") + axis[a] + " faces must be numbers");
        if (highMm[a] - lowMm[a] < spacing[a] * 0.999)
            throw Error(std::string("the crop box is ") + (highMm[a] < lowMm[a] ? "inside out" : "thinner than a voxel") +
                        " along " + axis[a] + " (" + std::to_string(lowMm[a]) + " to " + std::to_string(highMm[a]) +
                        " mm)");
        b.min[a] = std::clamp(lowMm[a] / length, 0.0, 1.0);
        b.max[a] = std::clamp(highMm[a] / length, 0.0, 1.0);
        if (b.max[a] - b.min[a] < 0.5 / double(dims[std::size_t(a)]))
            throw Error(std::string("the crop box lies outside the volume along ") + axis[a] + " (0 to " +
                        std::to_string(length) + " mm)");
    }
    return b;
}

std::array<glm::dvec3, 2> CropBox::millimetres(const std::array<std::uint32_t, 3>& dims, const glm::dvec3& spacing) const {
    const glm::dvec3 length{double(dims[0]) * spacing.x, double(dims[1]) * spacing.y, double(dims[2]) * spacing.z};
    return {min * length, max * length};
}

}  // namespace hvx::core
