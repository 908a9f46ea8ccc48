#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec4.hpp>

#include "core/appearance/Enhancers.h"
#include "core/image/RenderImage.h"
#include "core/reference/RenderSettings.h"
#include "core/octree/OctreeReader.h"
#include "core/appearance/ToolSet.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/SpatialIndex.h"
#include "core/appearance/TransferFunction.h"
#include "core/camera/View.h"

namespace hvx::core {

/// The CPU reference ray caster: walks the spatial index with the same traversal code as the
/// shader (core/streaming/IndexTraversal.glsl), samples bricks trilinearly with a step equal to
/// the leaf's voxel size and opacity corrected for it, composites front to back with the
/// pre-integrated transfer function (thesis Eq. 3.1) and stops at 0.99 opacity. Like the
/// shader, it steps over brick cells that cannot show (RenderSettings::skipEmptyCells); their
/// ranges are taken once, on construction. It is the oracle of the GPU tests and the headless
/// fallback of `holovox-cli render --cpu`. A label map (VolumeGeometry::isLabel) is sampled at
/// the nearest voxel and each sample classified by its own table entry
/// (TransferFunction::entry), so no label takes a neighbour's colour; gradients for shading
/// stay trilinear. A split-voxel octree (OctreeReader::splitVoxels) is drawn cell by cell
/// (thesis §4.5.2, SplitCellMarch), DVR only.
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
    friend class FusedRayCaster;  // samples, classifies and shades each of its two volumes
    glm::vec4 cast(const glm::dvec3& origin, const glm::dvec3& direction, float& depth,
                   std::vector<std::uint32_t>* counts) const;
    /// A split-voxel octree's ray (DVR): the cells of each leaf by SplitCellMarch.
    glm::vec4 castSplit(const glm::dvec3& origin, const glm::dvec3& direction, float& depth,
                        std::vector<std::uint32_t>* counts) const;
    /// A ray bent by Snell's law at each step (TransferFunction::hasRefraction; DVR), step for
    /// step as resources/shaders/raycast_refract.glsl (CpuRefractedRay.cpp).
    glm::vec4 castRefracted(const glm::dvec3& origin, const glm::dvec3& direction, float& depth,
                            std::vector<std::uint32_t>* counts) const;
    template <class Visitor>
    void walk(const glm::dvec3& origin, const glm::dvec3& direction, Visitor&& visit) const;
    /// What sampling a leaf's brick needs, worked out once per leaf a ray enters.
    struct Leaf {
        const float* data = nullptr;
        float scale = 1.0f;  // octree units -> level voxels
        glm::vec3 origin{};  // the brick's first sample, in level voxels, less the border
        int edge = 0;
        // The ancestors' bricks and origins (0: the parent; its scale is half the leaf's, and so
        // on up): for multilevel sampling (RenderSettings::multilevel) where the level field is
        // coarser than the leaf (blends), as far up as the field reaches, with the field at the
        // corners (SpatialIndex::LevelLink::coarser) and the leaf's box (corner, size); and the
        // parent for the detail shading's coarser gradient wherever it is resident.
        const float* ancestor[SpatialIndex::kLevelSpan] = {};
        glm::vec3 ancestorOrigin[SpatialIndex::kLevelSpan] = {};
        bool blends = false;
        float coarser[8] = {};
        float highest = 0.0f;  // the largest of them: the field's bound
        glm::vec3 lo{};
        float size = 1.0f;
    };
    /// `levels`: with multilevel sampling on, blend with the parent (off in the fused march).
    Leaf leaf(std::uint32_t node, const glm::vec3& leafLo, bool levels = true) const;
    float sample(const Leaf& leaf, const glm::vec3& p) const;  ///< trilinear, or nearest for labels
    /// Trilinear in the leaf's brick, blended with its ancestors' by the level field.
    float linear(const Leaf& leaf, const glm::vec3& p) const;
    /// Trilinear in one brick of `edge`^3 samples.
    static float trilinear(const float* data, int edge, float scale, const glm::vec3& origin, const glm::vec3& p);
    /// How many levels coarser than the leaf the level field is at p: the corners' values,
    /// interpolated trilinearly, at most the largest of them (the eight weights may sum to a
    /// rounding above 1, which would reach past the ancestors linked).
    static float levelOffset(const Leaf& leaf, const glm::vec3& p);
    float nearest(const Leaf& leaf, const glm::vec3& p) const;
    /// The average f (k, tau) of the segment from value a to b: pre-integrated, or for labels
    /// the entry of b; segmentExtinction: its tau alone.
    glm::dvec4 segment(float a, float b) const { return labels_ ? tf_.entry(b) : tf_.segment(a, b); }
    double segmentExtinction(float a, float b) const { return labels_ ? tf_.entry(b).w : tf_.segmentExtinction(a, b); }
    glm::vec3 gradient(const Leaf& leaf, const glm::vec3& p, float spread = 1.0f) const;
    /// The detail shading's coarser scale (brick_sampling.glsl's leafCoarserGradient): the
    /// parent level's gradient one parent voxel apart where the leaf has its parent, else its own
    /// at twice its spacing.
    glm::vec3 coarserGradient(const Leaf& leaf, const glm::vec3& p) const;
    /// Shades a sample of colour `base` seen along dw and scales its opacity `a` by gradient
    /// opacity, boundary enhancement and view-dependent transparency, with one gradient for all
    /// (raycast_march.glsl's shadeSample).
    glm::dvec3 shadeSample(const Leaf& leaf, const glm::vec3& p, const glm::dvec3& base, const glm::dvec3& dw,
                           double& a) const;
    /// Gradient opacity: a' = 1 − (1 − a)^g(|∇f|).
    double scaleByGradient(double a, double len) const;

    /// Which cells of a slot's brick may show, for the skipping above (all bits when off).
    std::uint64_t visibleCells(std::uint32_t slot) const {
        return slot < visibleCells_.size() ? visibleCells_[slot] : ~std::uint64_t(0);
    }
    /// A leaf's cells that may show: all of them where it blends with its parent, whose values
    /// its own brick's ranges do not bound.
    std::uint64_t leafCells(const Leaf& leaf, std::uint32_t slot) const {
        return leaf.blends ? ~std::uint64_t(0) : visibleCells(slot);  // a blending leaf: the parent's values are not bounded by its cells
    }

    const OctreeReader& reader_;
    const SpatialIndex& index_;
    const std::vector<std::shared_ptr<const std::vector<float>>>& slots_;
    const TransferFunction& tf_;
    RenderSettings settings_;
    bool labels_;
    OctreeSpace space_;
    glm::dmat3 normalToWorld_;
    double strengthPerGradient_ = 0.0;  // |∇f| (world) -> boundary strength
    bool refracting_ = false;
    bool multilevel_ = false;  // RenderSettings::multilevel, where it applies and the index is linked
    bool detailParents_ = false;  // the detail shading draws, and the index is linked to parents
    glsl::HvxTools packedTools;
    std::vector<std::uint64_t> visibleCells_;  // per slot; empty when nothing is skipped
};

}  // namespace hvx::core
