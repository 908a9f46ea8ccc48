// While moving, the GPU draws a cheaper frame that still shows the whole volume; once still,
// the next frame is the full-quality image.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/camera/InteractiveQuality.h"
#include "core/image/FrameReconstructor.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/OctreeScene.h"
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

// Quincunx sub-frames (thesis §3.3): each draws a quarter of the pixels, each pixel exactly as
// the full frame draws it; the four of one view rebuild its full frame exactly, and a moving
// orbit is rebuilt closer to its full frames than the same rays drawn at half resolution.
TEST(InteractiveFrames, QuincunxSubFramesRebuildTheFullFrame) {
    core::PhantomVoxelSource phantom({96, 96, 80}, 3, {400, 400, 400}, 10.0);
    test::OctreeScene scene(phantom);
    const auto& reader = scene.reader;
    auto& ws = *scene.ws;
    const auto& g = reader->geometry();
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", g.valueMin, g.valueMax, 1, 0, 4.0);
    const glm::dvec3 c = scene.centre();
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    using test::psnr;
    const auto view = core::View::orbit(c, 1100.0, 25.0, 10.0, 161, 120);  // odd width: a last column of one phase
    ws.converge({view}, tf, {}, 32);
    const auto full = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, view);
    core::FrameReconstructor rebuilt;
    for (int k = 0; k < 4; ++k) {
        core::RenderSettings rs;
        rs.subFrame = k;
        const auto sub = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, rs, view);
        const glm::ivec2 ph = core::FrameReconstructor::phase(k);
        std::size_t same = 0, drawn = 0;
        for (int y = ph.y; y < view.height; y += 2)
            for (int x = ph.x; x < view.width; x += 2) {
                const std::size_t i = std::size_t(y) * std::size_t(view.width) + std::size_t(x);
                same += sub.rgba[i] == full.rgba[i] && sub.depth[i] == full.depth[i];
                ++drawn;
            }
        EXPECT_EQ(same, drawn) << "sub-frame " << k << " draws its pixels as the full frame does";
        rebuilt.add(sub, k, 1);
    }
    EXPECT_EQ(rebuilt.add(gpu.render(*reader, ws.index(), ws.slotBricks(), tf, [] {
        core::RenderSettings rs;
        rs.subFrame = 0;
        return rs;
    }(), view), 0, 1).rgba, full.rgba) << "the cycle of one still view is its full frame";
    // An orbit of 2 degrees a frame: each frame one sub-frame, against the full frame and the
    // half-resolution frame drawn for the same view.
    core::FrameReconstructor moving;
    double recon = 0, half = 0;
    int n = 0;
    for (int f = 0; f < 16; ++f) {
        const auto v = core::View::orbit(c, 1100.0, 25.0 + 2.0 * f, 10.0, 160, 120);
        ws.converge({v}, tf, {}, 32);
        core::RenderSettings rs;
        rs.subFrame = moving.next();
        const auto& out = moving.add(gpu.render(*reader, ws.index(), ws.slotBricks(), tf, rs, v), rs.subFrame, std::uint64_t(f));
        const auto want = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, v);
        const auto small = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, v.scaled(0.5));
        core::RenderImage enlarged = want;
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x)
                enlarged.rgba[std::size_t(y) * std::size_t(v.width) + std::size_t(x)] =
                    small.rgba[std::size_t(std::min(small.height - 1, y / 2)) * std::size_t(small.width) +
                               std::size_t(std::min(small.width - 1, x / 2))];
        if (f < 4) continue;
        recon += psnr(out, want);
        half += psnr(enlarged, want);
        ++n;
    }
    std::printf("orbit 2 deg/frame: rebuilt from sub-frames %.1f dB, half resolution %.1f dB (mean PSNR against the full frames)\n",
                recon / n, half / n);
    EXPECT_GT(recon / n, half / n);
}
