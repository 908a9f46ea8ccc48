// Fusion benchmark (not a test): a second volume laid over the first in the same ray march
// (render::GpuRayCaster's HVX_FUSION variant, `holovox-cli render --overlay`), against the first
// volume alone, in the same run: frame time once warm, and bricks read from disk per frame
// while the view orbits a few degrees a frame.
//
//   build/release/tests/bench/hvx_bench_fusion [--dims 1024x1024x1024] [--size 512] [--frames 10]
//   Two CT phantoms (their own seeds) are built first into a temporary folder.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/appearance/ColorMap.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"

using namespace hvx;
using Clock = std::chrono::steady_clock;

namespace {
double ms(Clock::time_point a) { return std::chrono::duration<double, std::milli>(Clock::now() - a).count(); }

/// One volume as the 3D view holds it: reader, cache, loader, working set.
struct Layer {
    std::unique_ptr<core::OctreeReader> reader;
    std::unique_ptr<core::BrickCache> cache;
    std::unique_ptr<core::BrickLoader> loader;
    std::unique_ptr<core::WorkingSet> ws;
    explicit Layer(const std::string& path)
        : reader(core::OctreeReader::open(path)), cache(std::make_unique<core::BrickCache>(std::size_t(3) << 30)),
          loader(std::make_unique<core::BrickLoader>(*reader, *cache)) {
        core::WorkingSetOptions o;
        o.cpuMirror = false;
        o.maxBricks = 4096;
        ws = std::make_unique<core::WorkingSet>(*reader, *cache, *loader, o);
    }
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
    std::array<std::uint32_t, 3> dims{1024, 1024, 1024};
    int size = 512, frames = 10;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--dims")) dims = core::VoxelSourceFactory::parseDims(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--size")) size = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--frames")) frames = std::max(3, std::atoi(argv[i + 1]));
    }
    const auto dir = std::filesystem::temp_directory_path() / ("hvx-fusion-bench-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto t0 = Clock::now();
    std::vector<std::string> paths;
    for (int v = 0; v < 2; ++v) {
        core::PhantomVoxelSource phantom(dims, std::uint64_t(7 + v));
        core::JobContext job;
        paths.push_back((dir / ("v" + std::to_string(v) + ".hvo")).string());
        core::OctreeBuilder(core::BuildOptions{}).build(phantom, paths.back(), job);
    }
    std::printf("built two %ux%ux%u phantoms in %.1f s\n", dims[0], dims[1], dims[2], ms(t0) / 1000.0);
    Layer a(paths[0]), b(paths[1]);
    const auto& g = a.reader->geometry();
    const auto space = core::OctreeSpace::of(g, a.reader->brickSize(), a.reader->levelCount());
    const glm::dvec3 centre = space.centre();
    const glm::dvec3 corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const double radius = glm::length(centre - corner) / std::tan(glm::radians(15.0)) * 1.05;
    auto viewAt = [&](double azimuth) { return core::View::orbit(centre, radius, azimuth, 15, size, size); };
    const auto tf = core::TransferFunction::preset("ct-bone", g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                                   space.minSpacing);
    // The second volume as a PET-like overlay: soft tissue (0 to 200 HU) under the hot map.
    const auto& gb = b.reader->geometry();
    const auto tfB = core::TransferFunction::forColorMap(core::ColorMap::named("hot"), (0 - gb.rescaleIntercept) / gb.rescaleSlope,
                                                         (200 - gb.rescaleIntercept) / gb.rescaleSlope, 0.05, gb.valueMin,
                                                         gb.valueMax, space.minSpacing);
    render::EglOffscreenContext ctx;
    // One ray caster each (its pools hold its volumes' bricks): no frame re-uploads a pool.
    render::GpuRayCaster gpu, gpuA, gpuB;
    core::RenderSettings rs;
    const render::GpuRayCaster::Overlay overlay{*b.reader, b.ws->index(), b.ws->slotBricks(), tfB};

    // Warm: the view converged, then frames drawn with the cut as it stands.
    const auto still = viewAt(30);
    a.ws->converge({still}, tf);
    b.ws->converge({still}, tfB);
    std::printf("%s, %dx%d image; cuts of %zu and %zu bricks\n", ctx.info().renderer.c_str(), size, size,
                a.ws->stats().cutNodes, b.ws->stats().cutNodes);
    gpuA.render(*a.reader, a.ws->index(), a.ws->slotBricks(), tf, rs, still);
    gpu.render(*a.reader, a.ws->index(), a.ws->slotBricks(), tf, rs, still, &overlay);
    gpuB.render(*b.reader, b.ws->index(), b.ws->slotBricks(), tfB, rs, still);
    std::vector<double> alone, aloneB, fused;
    for (int f = 0; f < frames; ++f) {
        auto s = Clock::now();
        a.ws->update({still}, tf);
        gpuA.render(*a.reader, a.ws->index(), a.ws->slotBricks(), tf, rs, still);
        alone.push_back(ms(s));
        s = Clock::now();
        b.ws->update({still}, tfB);
        gpuB.render(*b.reader, b.ws->index(), b.ws->slotBricks(), tfB, rs, still);
        aloneB.push_back(ms(s));
        s = Clock::now();
        a.ws->update({still}, tf);
        b.ws->update({still}, tfB);
        gpu.render(*a.reader, a.ws->index(), a.ws->slotBricks(), tf, rs, still, &overlay);
        fused.push_back(ms(s));
    }
    std::printf("still view: the base volume alone %.1f ms/frame, the overlay alone %.1f ms/frame, fused %.1f ms/frame "
                "(%.2f x the base alone, %.2f x the two drawn one after the other), medians of %d\n",
                median(alone), median(aloneB), median(fused), median(fused) / std::max(1e-9, median(alone)),
                median(fused) / std::max(1e-9, median(alone) + median(aloneB)), frames);
    // Orbiting 2 degrees a frame: bricks read from disk per frame, each volume's working set
    // refined without waiting (as the 3D view does).
    const std::size_t before = a.loader->loadedCount() + b.loader->loadedCount();
    std::vector<double> orbit;
    for (int f = 0; f < frames; ++f) {
        const auto view = viewAt(30 + 2.0 * (f + 1));
        const auto s = Clock::now();
        a.ws->update({view}, tf);
        b.ws->update({view}, tfB);
        gpu.render(*a.reader, a.ws->index(), a.ws->slotBricks(), tf, rs, view, &overlay);
        orbit.push_back(ms(s));
    }
    std::printf("orbit, 2 degrees a frame: fused %.1f ms/frame (median), %.1f bricks read per frame for both volumes\n",
                median(orbit), double(a.loader->loadedCount() + b.loader->loadedCount() - before) / frames);
    std::filesystem::remove_all(dir);
    return 0;
}
