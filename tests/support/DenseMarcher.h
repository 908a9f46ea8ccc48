#pragma once
// An independent oracle for the ray casters: rays marched through the dense phantom (every
// voxel, computed, not read from an octree), one voxel a step, with its own trilinear
// interpolation and central-difference gradients in the volume's index space. It shares
// nothing with core's sampling, bricks, borders or traversal; only the camera's rays.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/glm.hpp>

#include "core/volume/PhantomVoxelSource.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::test {

class DenseMarcher {
public:
    DenseMarcher(const core::PhantomVoxelSource& source, const core::VolumeGeometry& g)
        : source_(source), dims_{int(g.dims[0]), int(g.dims[1]), int(g.dims[2])},
          toIndex_(glm::inverse(g.indexToPatient())),
          normalToWorld_(glm::transpose(glm::dmat3(glm::inverse(g.indexToPatient())))) {}

    /// Trilinear value at an index-space position (clamped to the voxel centres).
    double value(glm::dvec3 idx) const {
        const glm::dvec3 hi(dims_[0] - 1, dims_[1] - 1, dims_[2] - 1);
        idx = glm::clamp(idx, glm::dvec3(0), hi);
        const glm::ivec3 i0 = glm::min(glm::ivec3(idx), glm::ivec3(hi) - 1);
        const glm::dvec3 f = idx - glm::dvec3(i0);
        double acc = 0;
        for (int c = 0; c < 8; ++c) {
            const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
            const double w = (dx ? f.x : 1 - f.x) * (dy ? f.y : 1 - f.y) * (dz ? f.z : 1 - f.z);
            acc += w * source_.voxel(std::uint32_t(i0.x + dx), std::uint32_t(i0.y + dy), std::uint32_t(i0.z + dz));
        }
        return acc;
    }

    /// The gradient (central differences one voxel apart) at an index-space position, in world
    /// (patient) directions; its length is not in any particular unit.
    glm::dvec3 gradient(const glm::dvec3& idx) const {
        glm::dvec3 g;
        for (int a = 0; a < 3; ++a) {
            glm::dvec3 h(0.0);
            h[a] = 1.0;
            g[a] = (value(idx + h) - value(idx - h)) / 2.0;
        }
        return normalToWorld_ * g;
    }

    /// The ray (world origin, unit direction) in index space, and where it crosses the volume's
    /// box (voxel centres ± half a voxel), or the part of it between the fractions `lo` and `hi`
    /// of its extent (a crop box), in world mm along it; false when it misses.
    bool clip(const glm::dvec3& o, const glm::dvec3& d, glm::dvec3& oi, glm::dvec3& di, double& t0, double& t1,
              const glm::dvec3& lo = glm::dvec3(0.0), const glm::dvec3& hi = glm::dvec3(1.0)) const {
        oi = glm::dvec3(toIndex_ * glm::dvec4(o, 1.0));
        di = glm::dmat3(toIndex_) * d;
        t0 = 0;
        t1 = 1e300;
        for (int a = 0; a < 3; ++a) {
            const double n = double(dims_[std::size_t(a)]);
            double ta = (lo[a] * n - 0.5 - oi[a]) / di[a], tb = (hi[a] * n - 0.5 - oi[a]) / di[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        return t1 > t0;
    }

private:
    const core::PhantomVoxelSource& source_;
    std::array<int, 3> dims_;
    glm::dmat4 toIndex_;
    glm::dmat3 normalToWorld_;
};

}  // namespace hvx::test
