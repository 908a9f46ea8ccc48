// Cine benchmark (not a test): a 4D series played through its time points as the workstation's
// Cine dock does (one working set and brick cache per time point, one GPU ray caster, the
// neighbours' working sets refined after each frame), against one volume alone, in the same
// run: frame time, and bricks read from disk per frame once warm.
//
//   build/release/tests/bench/hvx_bench_cine [--dims 256x256x128] [--times 10] [--size 512] [--passes 3]
//   The time points are CT phantoms with their own seeds, built first into a temporary folder.
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

/// One time point as the workstation holds it: reader, cache, loader, working set.
struct TimePoint {
    std::shared_ptr<const core::OctreeReader> reader;
    std::unique_ptr<core::BrickCache> cache;
    std::unique_ptr<core::BrickLoader> loader;
    std::unique_ptr<core::WorkingSet> ws;
    TimePoint(const std::string& path, std::size_t cacheBytes)
        : reader(core::OctreeReader::open(path)), cache(std::make_unique<core::BrickCache>(cacheBytes)),
          loader(std::make_unique<core::BrickLoader>(*reader, *cache)) {
        core::WorkingSetOptions o;
        o.cpuMirror = false;
        ws = std::make_unique<core::WorkingSet>(*reader, *cache, *loader, o);
    }
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
    std::array<std::uint32_t, 3> dims{256, 256, 128};
    int times = 10, size = 512, passes = 3;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--dims")) dims = core::VoxelSourceFactory::parseDims(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--times")) times = std::max(2, std::atoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--size")) size = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--passes")) passes = std::max(2, std::atoi(argv[i + 1]));
    }
    const auto dir = std::filesystem::temp_directory_path() / ("hvx-cine-bench-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto t0 = Clock::now();
    std::vector<std::string> paths;
    for (int t = 0; t < times; ++t) {
        core::PhantomVoxelSource phantom(dims, std::uint64_t(100 + t));
        core::JobContext job;
        paths.push_back((dir / ("t" + std::to_string(t) + ".hvo")).string());
        core::OctreeBuilder(core::BuildOptions{}).build(phantom, paths.back(), job);
    }
    std::printf("built %d time points of %ux%ux%u in %.1f s\n", times, dims[0], dims[1], dims[2], ms(t0) / 1000.0);

    const std::size_t budget = std::size_t(2) << 30;  // the view's, shared as the Cine dock shares it
    std::vector<TimePoint> points;
    points.reserve(std::size_t(times));
    for (const auto& p : paths) points.emplace_back(p, budget / std::size_t(times));
    const auto& g = points.front().reader->geometry();
    const auto space = core::OctreeSpace::of(g, points.front().reader->brickSize(), points.front().reader->levelCount());
    const glm::dvec3 centre = space.centre();
    const glm::dvec3 corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const auto view = core::View::orbit(centre, glm::length(centre - corner) / std::tan(glm::radians(15.0)) * 1.05, 30, 15,
                                        size, size);
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", g.valueMin, g.valueMax, g.rescaleSlope,
                                                   g.rescaleIntercept, space.minSpacing);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    core::RenderSettings rs;

    // One volume alone, warm: its frame time.
    auto& first = points.front();
    first.ws->converge({view}, tf);
    gpu.render(*first.reader, first.ws->index(), first.ws->slotBricks(), tf, rs, view);
    std::vector<double> alone;
    for (int f = 0; f < times; ++f) {
        const auto a = Clock::now();
        first.ws->update({view}, tf);
        gpu.render(*first.reader, first.ws->index(), first.ws->slotBricks(), tf, rs, view);
        alone.push_back(ms(a));
    }

    // Cine: each frame refines the shown time point's cut (without waiting), draws it, and
    // refines its neighbours' for the same view (their loaders read meanwhile).
    auto loaded = [&] {
        std::size_t n = 0;
        for (const auto& p : points) n += p.loader->loadedCount();
        return n;
    };
    std::printf("%s, %dx%d image, one volume alone: %.1f ms/frame (median of %d)\n", ctx.info().renderer.c_str(), size,
                size, median(alone), times);
    // Warm-up: every time point seen once at full quality (its cut converged: read from disk).
    const auto w = Clock::now();
    for (auto& p : points) p.ws->converge({view}, tf);
    std::printf("warm-up: %zu bricks read for %d time points in %.1f s\n", loaded(), times, ms(w) / 1000.0);
    for (int pass = 0; pass < passes; ++pass) {
        std::vector<double> frame;
        const std::size_t before = loaded();
        for (int t = 0; t < times; ++t) {
            auto& p = points[std::size_t(t)];
            const auto a = Clock::now();
            p.ws->update({view}, tf);
            gpu.render(*p.reader, p.ws->index(), p.ws->slotBricks(), tf, rs, view);
            frame.push_back(ms(a));
            for (const int n : {(t + 1) % times, (t + times - 1) % times}) points[std::size_t(n)].ws->update({view}, tf);
        }
        std::printf("cine pass %d through %d time points: %.1f ms/frame (median; %.2f x one volume alone), "
                    "%.1f bricks read per frame\n",
                    pass + 1, times, median(frame), median(frame) / std::max(1e-9, median(alone)),
                    double(loaded() - before) / times);
    }
    points.clear();
    std::filesystem::remove_all(dir);
    return 0;
}
