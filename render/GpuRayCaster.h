#pragma once
#include <map>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "core/octree/Brick.h"
#include "core/streaming/BrickCells.h"
#include "core/reference/CpuRayCaster.h"
#include "render/ComputeProgram.h"

namespace hvx::render {

/// The single-pass GPU ray caster: a compute shader per mode (static variants) that walks the
/// spatial index with the shared traversal step and samples a brick pool texture. The pool is
/// one 3D texture split into edge^3 slots in the volume's own precision (R8 for 8-bit, R16 for
/// 16-bit, R32F for float volumes), updated from the working set's slots; each slot carries the
/// affine map from its normalised texels to stored values (lossy 8-bit bricks keep their codes).
/// The index and the transfer-function tables are uploaded as storage buffers each frame. With
/// RenderSettings::countRays, rays per index node are counted with SSBO atomics and returned
/// for the working set's visibility feedback.
///
/// Threading: GL thread only, with a current OpenGL 4.5 context.
class GpuRayCaster {
public:
    /// Texel format of the brick pool. Native: the volume's own precision (R8, R16, R32F).
    /// Float: R32F for every volume. Auto: native on a hardware GPU; float on a software
    /// rasteriser (Mesa llvmpipe), where pool memory is system RAM and 8-bit texels filter
    /// slower than float ones (MRI template 512²: R8 ~430 ms, R32F ~300 ms per frame).
    enum class PoolPrecision { Auto, Native, Float };

    explicit GpuRayCaster(PoolPrecision precision = PoolPrecision::Auto);
    ~GpuRayCaster();
    GpuRayCaster(const GpuRayCaster&) = delete;
    GpuRayCaster& operator=(const GpuRayCaster&) = delete;

    /// A second volume fused over the first in the same ray march (the HVX_FUSION variant;
    /// core::FusedRayCaster is its CPU reference): its own index, bricks (in a pool of its own)
    /// and transfer function. DVR only, without tools.
    struct Overlay {
        const core::OctreeReader& reader;
        const core::SpatialIndex& index;
        const std::vector<std::shared_ptr<const core::Brick>>& bricks;  // its working set's pool slots
        const core::TransferFunction& tf;
    };

    /// Renders one view and reads the image back (offscreen rendering, tests, CLI).
    core::RenderImage render(const core::OctreeReader& reader, const core::SpatialIndex& index,
                             const std::vector<std::shared_ptr<const core::Brick>>& slots,
                             const core::TransferFunction& tf, const core::RenderSettings& settings,
                             const core::View& view, const Overlay* overlay = nullptr);
    /// Renders several views of one size from the same index and pool in one dispatch (the
    /// layers of its z dimension): the views of a light-field frame. With countRays, the rays
    /// of all views are counted in the first image (an overlay's in its overlayRayCounts).
    std::vector<core::RenderImage> renderViews(const core::OctreeReader& reader, const core::SpatialIndex& index,
                                               const std::vector<std::shared_ptr<const core::Brick>>& slots,
                                               const core::TransferFunction& tf, const core::RenderSettings& settings,
                                               const std::vector<core::View>& views, const Overlay* overlay = nullptr);
    /// Bytes uploaded to the brick pools by the last render().
    std::size_t lastUploadBytes() const { return uploaded_; }
    /// Bytes the pool textures occupy on the GPU.
    std::size_t poolBytes() const { return pools_[0].bytes + pools_[1].bytes; }

private:
    struct SlotRecord {                // std430 mirror of raycast_inputs.glsl's SlotRecord
        glm::vec2 decode{1.0f, 0.0f};  // stored value = texel * x + y
        glm::uvec2 visible{~0u};       // the brick's cells that may show (64 bits)
    };
    /// One volume's brick pool: a 3D texture of edge^3 slots and what each slot holds.
    struct Pool {
        unsigned texture = 0;
        std::uint32_t edge = 0, row = 0, layer = 0, layers = 0;
        // What each slot holds; keeping the reference stops a freed brick's address from being
        // reused by a new brick and mistaken for it.
        std::vector<std::shared_ptr<const core::Brick>> content;
        std::vector<SlotRecord> records;
        std::vector<core::BrickCells> cells;  // per slot: value ranges of the brick's cells
        // A slot's visible cells are recomputed when its brick changes, and all of them when the
        // transfer function, mode or iso value changes (cellKey).
        std::vector<bool> cellsStale;
        std::uint64_t cellKey = 0;
        core::ScalarType type = core::ScalarType::Float32;
        bool split = false;  // RGBA16UI split-voxel cells (raycast_split.glsl), not samples
        std::size_t bytes = 0;
    };
    /// Brings a pool up to date with the working set's slots; returns the bytes uploaded.
    std::size_t uploadPool(Pool& pool, const std::vector<std::shared_ptr<const core::Brick>>& slots,
                           std::uint32_t brickSize, std::uint32_t border, core::ScalarType type, bool split = false);
    /// Writes a split-voxel brick's cells into its slot, one RGBA16UI texel each.
    static void uploadSplitBrick(Pool& pool, std::uint32_t slot, const core::Brick& brick, std::vector<std::uint16_t>& scratch);
    /// Which cells of each slot's brick may show (all of them when nothing is skipped).
    static void updateVisibleCells(Pool& pool, const std::vector<std::shared_ptr<const core::Brick>>& slots,
                                   const core::TransferFunction& tf, const core::RenderSettings& settings, bool skip,
                                   bool labels);

    std::map<int, std::unique_ptr<ComputeProgram>> programs_;
    static constexpr int kBuffers = 15;
    unsigned buffers_[kBuffers] = {};  // nodes, ropes, tf f, tf F, colour, depth, ray counts, frame, slot
                                       // records, tools, views, tf opacity (F.w, f.w), gradient opacity,
                                       // refraction (∫(ν − 1), ν − 1), index levels (multilevel)
    Pool pools_[2];                    // the volume's, and a fused volume's
    bool floatPool_ = false;
    std::size_t uploaded_ = 0;
};

}  // namespace hvx::render
