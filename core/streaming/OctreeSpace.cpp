#include "core/streaming/OctreeSpace.h"

#include <algorithm>
#include <cmath>

#include <glm/matrix.hpp>

namespace hvx::core {

OctreeSpace OctreeSpace::of(const VolumeGeometry& g, std::uint32_t brickSize, int levelCount) {
    OctreeSpace s;
    s.rootVoxels = double(brickSize) * std::ldexp(1.0, levelCount - 1);
    // octree p -> level-0 continuous voxel coordinate u = p * rootVoxels; voxel centre index = u - 0.5.
    glm::dmat4 toIndex(1.0);
    toIndex[0][0] = toIndex[1][1] = toIndex[2][2] = s.rootVoxels;
    toIndex[3] = glm::dvec4(-0.5, -0.5, -0.5, 1.0);
    s.octreeToPatient = g.indexToPatient() * toIndex;
    s.patientToOctree = glm::inverse(s.octreeToPatient);
    for (int a = 0; a < 3; ++a) s.extent[a] = g.dims[std::size_t(a)] / s.rootVoxels;
    s.minSpacing = std::min({g.spacing.x, g.spacing.y, g.spacing.z});
    s.maxSpacing = g.spacing;
    return s;
}

double OctreeSpace::voxelSize(int level) const {
    return std::max({maxSpacing.x, maxSpacing.y, maxSpacing.z}) * std::ldexp(1.0, level);
}

}  // namespace hvx::core
