#pragma once
#include "core/image/RenderImage.h"
#include "core/reference/CpuRayCaster.h"

namespace hvx::core {

/// Two volumes in one ray march, the CPU reference of the GPU's fusion variant
/// (resources/shaders/raycast_fusion.glsl): a base volume and a second one laid over it (PET
/// over CT, a label map over its image), each walked through its own spatial index and sampled
/// from its own bricks at every step, in its own index space (so different grids, spacings and
/// orientations meet exactly, through each volume's LPS transform). The ray runs through the
/// base volume's box (or crop box); a step is the finer of the two leaves' voxel sizes, and
/// only where both volumes are empty is space skipped. Each volume's segment is classified by
/// its own transfer function (pre-integrated, or by label entry for a label map) and shaded with
/// its own gradient, its opacity scaled by its own gradient-opacity curve where it has one; the
/// two are composited as one medium: opacity 1 − (1 − a₁)(1 − a₂), colour the opacity-weighted
/// mean. DVR only; no tools, no boundary enhancement.
///
/// Threading: render() spreads rows over ThreadPool::shared(); the object is immutable.
class FusedRayCaster {
public:
    /// Both casters are kept by reference; their settings' shading and steps come from `base`.
    FusedRayCaster(const CpuRayCaster& base, const CpuRayCaster& overlay);
    RenderImage render(const View& view) const;

private:
    struct Cursor;  // one volume's walk along a ray
    glm::vec4 cast(const glm::dvec3& origin, const glm::dvec3& direction, float& depth) const;
    const CpuRayCaster& a_;
    const CpuRayCaster& b_;
};

}  // namespace hvx::core
