#include "render/LightFieldRenderer.h"

#include <chrono>

namespace hvx::render {

std::vector<core::RenderImage> LightFieldRenderer::render(const core::OctreeReader& reader, core::WorkingSet& ws,
                                                          core::BrickLoader& loader, const core::TransferFunction& tf,
                                                          const core::RenderSettings& settings,
                                                          const std::vector<core::View>& views,
                                                          const core::AccuracyFunction& accuracy, GpuRayCaster* gpu,
                                                          bool converge, Stats* stats) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    int frames = 0;
    for (; frames < (converge ? 64 : 1); ++frames) {
        ws.update(views, tf, accuracy);
        if (!converge || ws.stats().settled()) break;
        loader.waitIdle();
    }
    const auto t1 = Clock::now();
    std::vector<core::RenderImage> out;
    out.reserve(views.size());
    for (const auto& v : views) {
        if (gpu) out.push_back(gpu->render(reader, ws.index(), ws.slotBricks(), tf, settings, v));
        else out.push_back(core::CpuRayCaster(reader, ws.index(), ws.slotData(), tf, settings).render(v));
    }
    if (stats) {
        stats->cutNodes = ws.stats().cutNodes;
        stats->loaded = loader.loadedCount();
        stats->refineFrames = frames + 1;
        stats->refineMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
        stats->renderMs = std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
    }
    return out;
}

}  // namespace hvx::render
