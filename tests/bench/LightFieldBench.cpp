// Light-field benchmark (not a test): views per second and megabeams per second for a display
// frame drawn from one working set with the display's accuracy s(z), against the same views
// drawn one at a time, each with its own working set at 1 voxel per pixel (the baseline, same
// run); and the working set's size with s(z) against the uniform target.
//
//   build/release/tests/bench/hvx_bench_lightfield FILE.hvo [--display holovizio-72] [--size WxH] [--views N]
//   e.g. a 45-view 8K quilt: --display looking-glass-65 --size 853x480 --views 45
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include <glm/geometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/camera/DisplayModel.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/LightFieldRenderer.h"

using namespace hvx;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE.hvo [--display PROFILE] [--size WxH] [--views N]\n", argv[0]);
        return 2;
    }
    std::string profile = "holovizio-72";
    int width = 0, height = 0, count = 0;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--display")) profile = argv[i + 1];
        else if (!std::strcmp(argv[i], "--size")) std::sscanf(argv[i + 1], "%dx%d", &width, &height);
        else if (!std::strcmp(argv[i], "--views")) count = std::atoi(argv[i + 1]);
    }
    const auto display = core::DisplayModel::load(profile);
    const auto reader = core::OctreeReader::open(argv[1]);
    const auto& g = reader->geometry();
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    const glm::dvec3 centre = space.centre();
    const glm::dvec3 corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const double scale = 0.9 * std::min(display.screenWidthMm, display.screenHeightMm) / (2.0 * glm::length(centre - corner));
    auto views = display.views(centre, {1, 0, 0}, {0, 0, 1}, 1.0, width, height, scale);
    if (count > 0 && count < int(views.size())) {  // an evenly spread subset
        std::vector<core::View> subset;
        for (int i = 0; i < count; ++i) subset.push_back(views[std::size_t(i) * views.size() / std::size_t(count)]);
        views = subset;
    }
    const auto tf = core::TransferFunction::preset(g.modality == "CT" ? "ct-bone" : "mr-default", g.valueMin, g.valueMax,
                                                   g.rescaleSlope, g.rescaleIntercept, space.minSpacing);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    core::WorkingSetOptions options;
    options.cpuMirror = false;
    options.maxBricks = 8192;
    const double beams = double(views.size()) * views[0].width * views[0].height;

    // One working set for the frame, with s(z).
    core::BrickCache cache(2ull << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSet ws(*reader, cache, loader, options);
    render::LightFieldRenderer::Stats warm, st;
    render::LightFieldRenderer::render(*reader, ws, loader, tf, {}, views, display.accuracyFunction(scale), &gpu, true, &warm);
    const auto t0 = Clock::now();
    render::LightFieldRenderer::render(*reader, ws, loader, tf, {}, views, display.accuracyFunction(scale), &gpu, false, &st);
    const double oneSet = std::chrono::duration<double>(Clock::now() - t0).count();
    std::printf("%s, %zu views of %dx%d (%.1f Mbeams): one working set with s(z): %.2f s/frame, %.1f views/s, %.2f "
                "Mbeams/s, cut of %zu bricks\n",
                display.name.c_str(), views.size(), views[0].width, views[0].height, beams / 1e6, oneSet,
                double(views.size()) / oneSet, beams / 1e6 / oneSet, warm.cutNodes);

    // Baseline: each view alone with its own working set at 1 voxel per pixel (warm cache).
    std::size_t cutSum = 0;
    const auto t1 = Clock::now();
    for (const auto& v : views) {
        core::WorkingSet own(*reader, cache, loader, options);
        render::LightFieldRenderer::Stats s1;
        render::LightFieldRenderer::render(*reader, own, loader, tf, {}, {v}, {}, &gpu, true, &s1);
        cutSum += s1.cutNodes;
    }
    const double separate = std::chrono::duration<double>(Clock::now() - t1).count();
    std::printf("baseline, each view with its own working set at 1 voxel/pixel: %.2f s/frame, %.1f views/s, %.2f "
                "Mbeams/s, mean cut %zu bricks; one-set / baseline time = %.2f\n",
                separate, double(views.size()) / separate, beams / 1e6 / separate, cutSum / views.size(),
                oneSet / separate);
    // The same single working set with a uniform 1 voxel-per-pixel target, for its size.
    core::WorkingSet uniform(*reader, cache, loader, options);
    render::LightFieldRenderer::Stats su;
    render::LightFieldRenderer::render(*reader, uniform, loader, tf, {}, {views.front()}, {}, &gpu,
                                       true, &su);
    std::printf("working set: %zu bricks with s(z) for all views, %zu bricks for one view at 1 voxel/pixel\n", warm.cutNodes,
                su.cutNodes);
    return 0;
}
