// While moving, the GPU draws a cheaper frame that still shows the whole volume; once still,
// the next frame is the full-quality image.
#include <gtest/gtest.h>

#include <chrono>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/camera/InteractiveQuality.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/TempDir.h"

using namespace hvx;

TEST(InteractiveFrames, MovingFramesAreCheaperAndCompleteAndStillFramesAreFullQuality) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({128, 128, 96}, 3, {400, 400, 400}, 10.0);
    core::JobContext job;
    core::OctreeBuilder({}).build(phantom, dir.file("p.hvo"), job);
    const auto reader = core::OctreeReader::open(dir.file("p.hvo"));
    const auto& g = reader->geometry();
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", g.valueMin, g.valueMax, 1, 0, 4.0);
    core::BrickCache cache(1u << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSet ws(*reader, cache, loader, {});
    const glm::dvec3 c = ws.space().centre();
    const auto view = core::View::orbit(c, 1100.0, 25.0, 10.0, 256, 256);
    ws.converge({view}, tf, {}, 32);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    core::InteractiveQuality quality({1.0, 0.25, 2.0});  // an impossible target: always reduce
    auto draw = [&](bool moving, double& ms) {
        const auto level = quality.next(moving);
        core::RenderSettings rs;
        rs.stepScale = level.stepScale;
        const auto t0 = std::chrono::steady_clock::now();
        auto img = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, rs, view.scaled(level.resolution));
        ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        quality.frameDone(level, ms);
        return img;
    };
    double fullMs = 0, movingMs = 0, ms = 0;
    const auto full = draw(false, fullMs);  // compiles the DVR variant, uploads the pool
    draw(false, fullMs);
    auto moving = draw(true, ms);
    movingMs = 1e30;
    for (int i = 0; i < 3; ++i) {  // best of three against noise
        moving = draw(true, ms);
        movingMs = std::min(movingMs, ms);
    }
    std::printf("full quality %.1f ms (%dx%d), moving %.1f ms (%dx%d, step x2)\n", fullMs, full.width, full.height,
                movingMs, moving.width, moving.height);
    EXPECT_LE(moving.width, full.width / 2);
    EXPECT_LT(movingMs, 0.6 * fullMs) << "a moving frame does at least 8x less work";
    // Complete: the reduced frame covers the body as the full one does.
    auto coverage = [](const core::RenderImage& im) {
        double a = 0;
        for (const auto& p : im.rgba) a += p.a;
        return a / double(im.rgba.size());
    };
    EXPECT_NEAR(coverage(moving), coverage(full), 0.1 * coverage(full));
    // Still again: the very next frame is the full-quality image.
    double stillMs = 0;
    const auto still = draw(false, stillMs);
    ASSERT_EQ(still.width, full.width);
    for (std::size_t i = 0; i < full.rgba.size(); ++i) ASSERT_EQ(still.rgba[i], full.rgba[i]) << "pixel " << i;
}
