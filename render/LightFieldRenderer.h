#pragma once
#include <vector>

#include "core/base/JobContext.h"
#include "core/streaming/BrickLoader.h"
#include "core/reference/CpuRayCaster.h"
#include "core/camera/DisplayModel.h"
#include "core/streaming/WorkingSet.h"
#include "render/GpuRayCaster.h"

namespace hvx::render {

/// Draws all views of a multi-view display frame from one working set: the cut is refined
/// once for every view together with the display's accuracy function s(z) (DESIGN.md decision
/// 4), then the views are ray cast from that same index and pool, a batch of views per dispatch
/// (GpuRayCaster::renderViews; the batch keeps the output near 64 MiB). With
/// `gpu` null the CPU reference draws (the working set must keep its CPU mirror). A second
/// volume may be fused over the first in every view (DVR without the tools), its own cut
/// refined for the same views and accuracy.
///
/// Threading: the GL thread when `gpu` is given.
class LightFieldRenderer {
public:
    struct Stats {
        std::size_t cutNodes = 0, loaded = 0;
        int refineFrames = 0;
        double refineMs = 0, renderMs = 0;
    };
    /// A volume fused over the first (GpuRayCaster::Overlay, core::FusedRayCaster): its reader,
    /// working set and transfer function.
    struct Fused {
        const core::OctreeReader& reader;
        core::WorkingSet& ws;
        const core::TransferFunction& tf;
    };
    /// `converge`: load until the cut is final (synchronous mode) before drawing. `job`, when
    /// given, hears the progress (the cut, then each batch of views) and may cancel between them.
    static std::vector<core::RenderImage> render(const core::OctreeReader& reader, core::WorkingSet& ws,
                                                 core::BrickLoader& loader, const core::TransferFunction& tf,
                                                 const core::RenderSettings& settings, const std::vector<core::View>& views,
                                                 const core::AccuracyFunction& accuracy, GpuRayCaster* gpu,
                                                 bool converge, Stats* stats = nullptr, core::JobContext* job = nullptr,
                                                 const Fused* fused = nullptr);
};

}  // namespace hvx::render
