#include "render/LightFieldRenderer.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "core/base/Error.h"
#include "core/reference/FusedRayCaster.h"

namespace hvx::render {

std::vector<core::RenderImage> LightFieldRenderer::render(const core::OctreeReader& reader, core::WorkingSet& ws,
                                                          core::BrickLoader& loader, const core::TransferFunction& tf,
                                                          const core::RenderSettings& settings,
                                                          const std::vector<core::View>& views,
                                                          const core::AccuracyFunction& accuracy, GpuRayCaster* gpu,
                                                          bool converge, Stats* stats, core::JobContext* job,
                                                          const Fused* fused) {
    if (fused && (settings.mode != core::RenderSettings::Mode::Dvr || settings.tools.variantBits()))
        throw core::Error("two volumes are fused in DVR, without the illustrative tools");
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    if (job) job->report(0.0, "refining the cut for all views");
    const int frames = ws.converge(views, tf, accuracy, converge ? 64 : 1);
    if (fused) fused->ws.converge(views, fused->tf, accuracy, converge ? 64 : 1);
    const auto t1 = Clock::now();
    if (job) job->throwIfCancelled();
    std::vector<core::RenderImage> out;
    out.reserve(views.size());
    if (gpu) {
        // Batches of views per dispatch, as many as keep the output buffers near 64 MiB.
        const std::size_t perView = std::size_t(views.front().width) * std::size_t(views.front().height) * 20;
        const std::size_t batch = std::max<std::size_t>(1, (std::size_t(64) << 20) / std::max<std::size_t>(1, perView));
        for (std::size_t first = 0; first < views.size(); first += batch) {
            const std::vector<core::View> some(views.begin() + std::ptrdiff_t(first),
                                               views.begin() + std::ptrdiff_t(std::min(views.size(), first + batch)));
            if (job) {
                job->report(0.2 + 0.8 * double(first) / double(views.size()),
                            "views " + std::to_string(first + 1) + " to " + std::to_string(first + some.size()) + " of " +
                                std::to_string(views.size()));
                job->throwIfCancelled();
            }
            const GpuRayCaster::Overlay overlay{fused ? fused->reader : reader, fused ? fused->ws.index() : ws.index(),
                                                fused ? fused->ws.slotBricks() : ws.slotBricks(), fused ? fused->tf : tf};
            auto images = gpu->renderViews(reader, ws.index(), ws.slotBricks(), tf, settings, some, fused ? &overlay : nullptr);
            for (auto& im : images) out.push_back(std::move(im));
        }
    } else {
        const core::CpuRayCaster cpu(reader, ws.index(), ws.slotData(), tf, settings);
        if (fused) {
            core::RenderSettings uncropped = settings;  // the partner is cut by the base volume's box
            uncropped.crop = {};
            const core::CpuRayCaster second(fused->reader, fused->ws.index(), fused->ws.slotData(), fused->tf, uncropped);
            const core::FusedRayCaster both(cpu, second);
            for (const auto& v : views) out.push_back(both.render(v));
        } else {
            for (const auto& v : views) out.push_back(cpu.render(v));
        }
    }
    if (stats) {
        stats->cutNodes = ws.stats().cutNodes;
        stats->loaded = loader.loadedCount();
        stats->refineFrames = frames;
        stats->refineMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
        stats->renderMs = std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
    }
    return out;
}

}  // namespace hvx::render
