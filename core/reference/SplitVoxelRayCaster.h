#pragma once
#include "core/appearance/TransferFunction.h"
#include "core/camera/View.h"
#include "core/image/RenderImage.h"
#include "core/octree/SplitVoxelGrid.h"
#include "core/reference/RenderSettings.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// The CPU reference of split-voxel rendering (thesis §4.5.2, Fig. 4.5): a 3D DDA enumerates
/// the cells a ray crosses, front to back; a uniform cell adds its value's contribution over the
/// length inside it, a split cell adds its two materials on either side of the plane, in the
/// order the ray meets them, both shaded with the plane's normal. Extinction-weighted colours
/// (TransferFunction: k = tau·c), opacity 1 − exp(−tau·δt) per segment, front-to-back
/// compositing to RenderSettings::earlyTermination. Labels are classified by their own table
/// entry, intensities by the table at the value; values are never blended, so no pixel takes a
/// colour neither material has.
///
/// Shading (RenderSettings' Phong terms, headlight): split cells by their plane's normal; a
/// uniform cell entered across a face from a cell of another material by that face's normal
/// (the boundary then lies on the face); inside a material, ambient + diffuse, as Holovox shades
/// homogeneous regions elsewhere (the thesis uses the ambient term alone there).
///
/// Threading: render() spreads rows over ThreadPool::shared(); the object is immutable.
class SplitVoxelRayCaster {
public:
    SplitVoxelRayCaster(const SplitVoxelGrid& grid, const VolumeGeometry& geometry, const TransferFunction& tf,
                        RenderSettings settings);
    RenderImage render(const View& view) const;

private:
    glm::vec4 cast(const glm::dvec3& origin, const glm::dvec3& direction, float& depth) const;

    const SplitVoxelGrid& grid_;
    const TransferFunction& tf_;
    RenderSettings settings_;
    bool labels_;
    glm::dmat4 worldToCell_;   // patient mm -> cell coordinates
    glm::dmat3 cellNormalToWorld_;
    glm::dvec3 extent_;        // the volume's box in cell coordinates: [0, extent)
};

}  // namespace hvx::core
