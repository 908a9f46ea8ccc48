#pragma once
#include "core/appearance/ToolSet.h"
#include "core/volume/CropBox.h"

namespace hvx::core {

/// How to render: the mode, shading and stepping shared by the CPU reference and the GPU.
struct RenderSettings {
    enum class Mode { Dvr, Iso, Mip, MinIp, Average };
    Mode mode = Mode::Dvr;
    double isoValue = 0.0;           ///< stored units
    bool shading = true;             ///< Phong with central-difference gradients (DVR, iso)
    double ambient = 0.35, diffuse = 0.65, specular = 0.25, shininess = 24.0;
    /// Boundary enhancement (Rheingans & Ebert, as in Bruckner's illustrative DVR): opacity is
    /// scaled by (1 - b + b·|∇f|^), so homogeneous regions fade and boundaries stay. 0 = off.
    double boundary = 0.0;
    /// View-dependent transparency: opacity is scaled by (1 - v·|∇f|^·|n·V|), so boundaries
    /// facing the viewer turn transparent and silhouettes stay. 0 = off.
    double viewTransparency = 0.0;
    /// Multilevel shading (thesis §3.2.2, Fig. 3.7; core::glsl::hvxDetailShading), against the
    /// gradient at twice the voxel spacing: normal unsharp masking k (0 = off, up to 8) and
    /// exaggerated shading (0 = off, 1 = all). DVR and isosurface with Phong shading, without
    /// the illustrative tools, a fused volume or split-voxels (they keep their own shading).
    double normalUnsharp = 0.0;
    double exaggeratedShading = 0.0;
    bool detailShading() const {
        return shading && (mode == Mode::Dvr || mode == Mode::Iso) && (normalUnsharp > 0.0 || exaggeratedShading > 0.0);
    }
    /// Multilevel sampling (thesis §3.2.2, Fig. 3.6): a leaf that a coarser leaf touches blends
    /// its samples with its parent's, trilinear at both levels and weighted trilinearly by which
    /// of its corners the coarser leaf touches (quadrilinear), so that bricks of neighbouring
    /// levels meet without a seam. Trilinear scalar volumes: not label maps, nearest-neighbour
    /// reconstruction, split-voxels or a fused volume, which sample their leaf's level alone.
    bool multilevel = false;
    double earlyTermination = 0.99;
    double stepScale = 1.0;          ///< step = stepScale × the local voxel size
    bool countRays = false;          ///< fill RenderImage::rayCounts (visibility feedback)
    /// Step over the cells of a brick (core::BrickCells) that cannot show: transparent under
    /// the transfer function (DVR) or not holding the iso value. The image is the same either
    /// way; off only for the tests that show it.
    bool skipEmptyCells = true;
    /// Nearest-neighbour reconstruction: each sample takes its voxel's value (a label map
    /// always does); the thesis's Fig. 4.6 compares it with trilinear and split-voxels.
    bool nearest = false;
    /// 0–3: the GPU ray caster draws only the pixels of this quincunx sub-frame
    /// (core::FrameReconstructor::phase), leaving the others as they were; -1: every pixel.
    /// The CPU reference always draws every pixel.
    int subFrame = -1;
    ToolSet tools;                   ///< illustrative tools (DVR only)
    CropBox crop;                    ///< rays start and end at its faces (every mode)
};

/// Emission added to ambient light where a tool emphasises tissue (the clip plane's slab).
constexpr double kEmphasisEmission = 0.5;

/// |∇f|^ above: the gradient's strength in [0, 1], the value change per finest voxel as a
/// fraction of the transfer function's range, where 10% of the range per voxel counts as a full
/// boundary.
constexpr double kBoundaryGradientFraction = 0.1;

}  // namespace hvx::core
