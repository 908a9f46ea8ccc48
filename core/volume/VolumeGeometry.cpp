#include "core/volume/VolumeGeometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"

namespace hvx::core {

glm::dmat4 VolumeGeometry::indexToPatient() const {
    glm::dmat4 m(1.0);
    for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r) m[c][r] = direction[c][r] * spacing[c];
    }
    m[3] = glm::dvec4(origin, 1.0);
    return m;
}

bool VolumeGeometry::isModalityCode(const std::string& code) {
    return code.size() >= 2 && code.size() <= 8 &&
           std::all_of(code.begin(), code.end(), [](char c) { return c >= 'A' && c <= 'Z'; });
}

glm::dvec3 VolumeGeometry::nearestVoxelCentre(const glm::dvec3& patient) const {
    const glm::dmat4 toPatient = indexToPatient();
    const glm::dvec3 index(glm::inverse(toPatient) * glm::dvec4(patient, 1.0));
    return glm::dvec3(toPatient * glm::dvec4(glm::round(index), 1.0));
}

glm::dvec3 VolumeGeometry::onNearestLayer(const glm::dvec3& patient, const glm::dvec3& normal) const {
    const glm::dmat4 toIndex = glm::inverse(indexToPatient());
    const glm::dvec3 index(toIndex * glm::dvec4(patient, 1.0));
    for (int a = 0; a < 3; ++a) {
        // index a's gradient in patient space: the normal of the layers index a = const
        const glm::dvec3 g(toIndex[0][a], toIndex[1][a], toIndex[2][a]);
        const double along = glm::dot(g, normal);
        if (std::abs(along) < (1.0 - 1e-9) * glm::length(g)) continue;
        return patient + normal * ((std::round(index[a]) - index[a]) / along);
    }
    return patient;
}

void VolumeGeometry::validate(const std::string& what) const {
    for (int a = 0; a < 3; ++a) {
        if (dims[a] == 0) throw Error(what + ": volume has a zero dimension");
        if (dims[a] > 65535u * 16u) throw Error(what + ": dimension " + std::to_string(dims[a]) + " is too large");
        if (!(spacing[a] > 0.0) || !std::isfinite(spacing[a]))
            throw Error(what + ": voxel spacing must be positive and finite");
        double len = std::sqrt(direction[a][0] * direction[a][0] + direction[a][1] * direction[a][1] +
                               direction[a][2] * direction[a][2]);
        if (!(std::abs(len - 1.0) <= 1e-3)) throw Error(what + ": direction cosines are not unit vectors");  // NaN too
    }
    // Axes less than about 0.06 degrees apart span no volume: a file's error, not a shear.
    if (!(std::abs(glm::determinant(direction)) >= 1e-3))
        throw Error(what + ": direction cosines are dependent (two axes are parallel)");
    // A patient lies within metres of the scanner's origin; a kilometre away is a broken header.
    const glm::dmat4 toPatient = indexToPatient();
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 index((corner & 1) ? dims[0] - 1.0 : 0.0, (corner & 2) ? dims[1] - 1.0 : 0.0,
                               (corner & 4) ? dims[2] - 1.0 : 0.0);
        const glm::dvec3 p(toPatient * glm::dvec4(index, 1.0));
        if (!(std::abs(p.x) <= kMaxPatientMm && std::abs(p.y) <= kMaxPatientMm && std::abs(p.z) <= kMaxPatientMm))
        {
            char at[96];
            std::snprintf(at, sizeof at, "%.6g, %.6g, %.6g", p.x, p.y, p.z);
            throw Error(what + ": its voxels lie more than 1 km from the patient coordinates' origin (one at " + at +
                        " mm): not a patient's position");
        }
    }
    if (!std::isfinite(rescaleSlope) || rescaleSlope == 0.0 || !std::isfinite(rescaleIntercept))
        throw Error(what + ": invalid rescale slope/intercept");
}

}  // namespace hvx::core

namespace hvx::core {

std::string VolumeGeometry::gridDifference(const VolumeGeometry& o) const {
    auto dimsText = [](const std::array<std::uint32_t, 3>& d) {
        return std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]);
    };
    if (dims != o.dims) return "dimensions " + dimsText(o.dims) + ", not " + dimsText(dims);
    const double tolerance = 1e-3 * std::min({spacing.x, spacing.y, spacing.z});
    for (int a = 0; a < 3; ++a) {
        if (std::abs(spacing[a] - o.spacing[a]) > tolerance) return "another voxel spacing";
        if (glm::length(direction[a] - o.direction[a]) > 1e-5) return "another orientation";
    }
    if (glm::length(origin - o.origin) > tolerance) return "another position";
    if (rescaleSlope != o.rescaleSlope || rescaleIntercept != o.rescaleIntercept)
        return "another rescale (slope " + std::to_string(o.rescaleSlope) + ", intercept " +
               std::to_string(o.rescaleIntercept) + ")";
    if (scalarType != o.scalarType) return "another stored type";
    return {};
}

}  // namespace hvx::core
