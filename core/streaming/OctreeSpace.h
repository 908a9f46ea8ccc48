#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// Maps between patient space (LPS mm) and octree space, where the root node is the unit cube
/// and level-0 voxel i spans [i, i+1) / (brick * 2^(levels-1)). The volume occupies
/// [0, extent] of it (branch on need: the rest is outside).
struct OctreeSpace {
    glm::dmat4 octreeToPatient{1.0};
    glm::dmat4 patientToOctree{1.0};
    glm::dvec3 extent{1.0};   ///< the volume's box in octree space is [0, extent]
    double rootVoxels = 1.0;  ///< level-0 voxels across the root: brick * 2^(levels-1)
    double minSpacing = 1.0;  ///< smallest voxel spacing (mm)

    static OctreeSpace of(const VolumeGeometry& g, std::uint32_t brickSize, int levelCount);
    /// The centre of the volume's box, in patient coordinates (LPS mm).
    glm::dvec3 centre() const { return glm::dvec3(octreeToPatient * glm::dvec4(extent * 0.5, 1.0)); }
    /// World length (mm) of one level-`level` voxel (the largest axis).
    double voxelSize(int level) const;
    glm::dvec3 maxSpacing{1.0};
};

}  // namespace hvx::core
