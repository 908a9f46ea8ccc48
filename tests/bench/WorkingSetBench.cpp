// Working-set benchmark (not a test): a scripted orbit around an .hvo (a phantom of 32 GiB of
// voxels in the README), with a 2 GiB CPU brick cache and asynchronous loading as in the GUI.
// Reports the time from a cold start to the first complete cut, refinement time and bricks
// loaded per frame, and peak RSS against the cache budget.
//
//   build/release/tests/bench/hvx_bench_workingset FILE.hvo [--cache-mb 2048] [--size 1024]
//        [--frames 36] [--bricks 8192] [--tf ct-bone] [--zoom 1]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/WorkingSet.h"

using namespace hvx;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE.hvo [--cache-mb N] [--size N] [--frames N] [--bricks N] [--tf P]\n", argv[0]);
        return 2;
    }
    std::size_t cacheMb = 2048, bricks = 8192;
    int size = 1024, frames = 36;
    std::string preset = "ct-bone";
    double zoom = 1.0;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        if (k == "--cache-mb") cacheMb = std::stoul(argv[i + 1]);
        else if (k == "--size") size = std::stoi(argv[i + 1]);
        else if (k == "--frames") frames = std::stoi(argv[i + 1]);
        else if (k == "--bricks") bricks = std::stoul(argv[i + 1]);
        else if (k == "--tf") preset = argv[i + 1];
        else if (k == "--zoom") zoom = std::stod(argv[i + 1]);
    }
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const auto reader = core::OctreeReader::open(argv[1]);
    const auto& g = reader->geometry();
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    const auto tf = core::TransferFunction::preset(preset, g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                                   space.minSpacing);
    core::BrickCache cache(cacheMb << 20);
    core::BrickLoader loader(*reader, cache, 2);
    core::WorkingSetOptions opt;
    opt.maxBricks = bricks;
    opt.cpuMirror = false;
    core::WorkingSet ws(*reader, cache, loader, opt);
    const glm::dvec3 centre = space.centre();
    const glm::dvec3 corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const double radius = glm::length(centre - corner) / std::tan(glm::radians(15.0)) * 1.05 / zoom;
    auto viewAt = [&](double az) { return core::View::orbit(centre, radius, az, 20.0, size, size); };

    std::printf("%s: %u x %u x %u %s (%.1f GiB of voxels), %zu nodes; cache %zu MiB, pool %zu bricks, %dx%d, zoom %.1f\n",
                argv[1], g.dims[0], g.dims[1], g.dims[2], std::string(core::scalarName(g.scalarType)).c_str(),
                double(g.byteSize()) / (1u << 30), reader->nodes().size(), cacheMb, bricks, size, size, zoom);
    // Cold start: frames at ~30 Hz until nothing is waited for any more (the cut is complete,
    // or as fine as the pool budget allows).
    int coldFrames = 0;
    const auto frameTime = std::chrono::milliseconds(33);
    for (; coldFrames < 3000; ++coldFrames) {
        const auto f0 = Clock::now();
        ws.update({viewAt(0)}, tf);
        if (ws.stats().settled()) break;
        if (coldFrames % 25 == 0)
            std::fprintf(stderr, "  frame %d: %zu bricks, %zu requested, refine %.1f ms, %zu loaded\n", coldFrames,
                         ws.stats().cutNodes, ws.stats().requested, ws.stats().refineMs, loader.loadedCount());
        std::this_thread::sleep_until(f0 + frameTime);
    }
    const double cold = std::chrono::duration<double>(Clock::now() - start).count();
    std::printf("cold start to the first %s cut: %.2f s (%d frames), %zu bricks in the cut, %zu loaded, refine %.1f ms\n",
                ws.stats().complete ? "complete" : "budget-limited", cold, coldFrames + 1, ws.stats().cutNodes,
                loader.loadedCount(), ws.stats().refineMs);
    std::fflush(stdout);
    // Orbit: 10 degrees per frame, loading in the background, never waiting.
    double refineSum = 0, refineMax = 0, levelsSum = 0, levelsMax = 0;
    std::size_t blendingSum = 0, steepSum = 0, cutSum = 0, rebuilt = 0;
    std::uint32_t reachMax = 0;
    std::size_t loadedBefore = loader.loadedCount(), loadsMax = 0, complete = 0;
    for (int f = 1; f <= frames; ++f) {
        const auto f0 = Clock::now();
        const std::size_t l0 = loader.loadedCount();
        ws.update({viewAt(10.0 * f)}, tf);
        refineSum += ws.stats().refineMs;
        refineMax = std::max(refineMax, ws.stats().refineMs);
        levelsSum += ws.stats().levelsMs;
        levelsMax = std::max(levelsMax, ws.stats().levelsMs);
        blendingSum += ws.stats().blendingLeaves;
        steepSum += ws.stats().steepLeaves;
        reachMax = std::max(reachMax, ws.index().levelReach);
        cutSum += ws.stats().cutNodes;
        rebuilt += ws.stats().indexRebuilt;
        complete += ws.stats().complete;
        std::this_thread::sleep_until(f0 + frameTime);
        loadsMax = std::max(loadsMax, loader.loadedCount() - l0);
    }
    std::printf("of which linking leaves to parents (multilevel sampling): %.3f ms/frame (max %.3f; the index built "
                "anew in %zu of %d frames), %.1f of %.1f cut leaves blending per frame, %.1f of them clamped (the level field "
                "reaching past the resident ancestors or six levels: a seam remains); the field reaches %u levels up at most\n",
                levelsSum / frames, levelsMax, rebuilt, frames, double(blendingSum) / frames, double(cutSum) / frames,
                double(steepSum) / frames, reachMax);
    struct rusage ru {};
    getrusage(RUSAGE_SELF, &ru);
    const double rssMiB = double(ru.ru_maxrss) / 1024.0;
    std::printf("orbit of %d frames at 30 Hz: refinement %.2f ms/frame (max %.2f), %.1f bricks loaded/frame "
                "(max %zu), %zu frames complete\n",
                frames, refineSum / frames, refineMax, double(loader.loadedCount() - loadedBefore) / frames, loadsMax,
                complete);
    std::printf("peak RSS %.0f MiB against a cache budget of %zu MiB (target: at most budget + 300 MiB)\n", rssMiB, cacheMb);
    return 0;
}
