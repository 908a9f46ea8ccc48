#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec4.hpp>

#include "core/Enhancers.h"
#include "core/OctreeReader.h"
#include "core/ToolSet.h"
#include "core/OctreeSpace.h"
#include "core/SpatialIndex.h"
#include "core/TransferFunction.h"
#include "core/View.h"

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
    double earlyTermination = 0.99;
    double stepScale = 1.0;          ///< step = stepScale × the local voxel size
    bool countRays = false;          ///< fill RenderImage::rayCounts (visibility feedback)
    /// Step over the cells of a brick (core::BrickCells) that cannot show: transparent under
    /// the transfer function (DVR) or not holding the iso value. The image is the same either
    /// way; off only for the tests that show it.
    bool skipEmptyCells = true;
    ToolSet tools;                   ///< illustrative tools (DVR only)
};

/// Emission added to ambient light where a tool emphasises tissue (the clip plane's slab).
constexpr double kEmphasisEmission = 0.5;

/// |∇f|^ above: the gradient's strength in [0, 1], the value change per finest voxel as a
/// fraction of the transfer function's range, where 10% of the range per voxel counts as a full
/// boundary.
constexpr double kBoundaryGradientFraction = 0.1;

/// A rendered frame: premultiplied RGBA (linear floats), depth (world mm along the ray to the
/// first significant sample, +inf when none) and, on request, rays per index node.
struct RenderImage {
    int width = 0, height = 0;
    std::vector<glm::vec4> rgba;
    std::vector<float> depth;
    std::vector<std::uint32_t> rayCounts;
};

/// The CPU reference ray caster: walks the spatial index with the same traversal code as the
/// shader (core/shared/IndexTraversal.glsl), samples bricks trilinearly with a step equal to
/// the leaf's voxel size and opacity corrected for it, composites front to back with the
/// pre-integrated transfer function (thesis Eq. 3.1) and stops at 0.99 opacity. Like the
/// shader, it steps over brick cells that cannot show (RenderSettings::skipEmptyCells); their
/// ranges are taken once, on construction. It is the oracle of the GPU tests and the headless
/// fallback of `holovox-cli render --cpu`.
///
/// Threading: render() spreads rows over ThreadPool::shared(); the object is immutable.
class CpuRayCaster {
public:
    CpuRayCaster(const OctreeReader& reader, const SpatialIndex& index,
                 const std::vector<std::shared_ptr<const std::vector<float>>>& slots, const TransferFunction& tf,
                 RenderSettings settings);
    RenderImage render(const View& view) const;

    /// One leaf visit of a ray: index node and world-space parameter interval.
    struct Visit {
        std::uint32_t node;
        float tIn, tOut;
    };
    /// The leaves a world-space ray crosses, front to back (for tests and debugging).
    std::vector<Visit> traverse(const glm::dvec3& origin, const glm::dvec3& direction) const;

private:
    glm::vec4 cast(const glm::dvec3& origin, const glm::dvec3& direction, float& depth,
                   std::vector<std::uint32_t>* counts) const;
    template <class Visitor>
    void walk(const glm::dvec3& origin, const glm::dvec3& direction, Visitor&& visit) const;
    /// What sampling a leaf's brick needs, worked out once per leaf a ray enters.
    struct Leaf {
        const float* data = nullptr;
        float scale = 1.0f;  // octree units -> level voxels
        glm::vec3 origin{};  // the brick's first sample, in level voxels, less the border
        int edge = 0;
    };
    Leaf leaf(std::uint32_t node, const glm::vec3& leafLo) const;
    float sample(const Leaf& leaf, const glm::vec3& p) const;
    glm::vec3 gradient(const Leaf& leaf, const glm::vec3& p, float spread = 1.0f) const;

    /// Which cells of a slot's brick may show, for the skipping above (all bits when off).
    std::uint64_t visibleCells(std::uint32_t slot) const {
        return slot < visibleCells_.size() ? visibleCells_[slot] : ~std::uint64_t(0);
    }

    const OctreeReader& reader_;
    const SpatialIndex& index_;
    const std::vector<std::shared_ptr<const std::vector<float>>>& slots_;
    const TransferFunction& tf_;
    RenderSettings settings_;
    OctreeSpace space_;
    glm::dmat3 normalToWorld_;
    glsl::HvxTools packedTools;
    std::vector<std::uint64_t> visibleCells_;  // per slot; empty when nothing is skipped
};

}  // namespace hvx::core
