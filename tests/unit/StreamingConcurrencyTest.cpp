// The loader's threads fill a CPU cache smaller than the working set while the view keeps
// moving, as in the workstation: the cache keeps its budget, nothing fails, and once the view
// stops the image is the one a cache with room for everything gives.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "core/octree/OctreeBuilder.h"
#include "core/reference/CpuRayCaster.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/WorkingSet.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
core::View orbitView(const core::OctreeReader& r, double azimuth) {
    const auto s = core::OctreeSpace::of(r.geometry(), r.brickSize(), r.levelCount());
    return core::View::orbit(s.centre(), 900.0, azimuth, 15.0, 96, 96);
}

core::RenderImage settledImage(const core::OctreeReader& r, core::WorkingSet& ws, const core::View& view,
                               const core::TransferFunction& tf) {
    ws.converge({view}, tf, {}, 400);
    EXPECT_TRUE(ws.stats().complete);
    return core::CpuRayCaster(r, ws.index(), ws.slotData(), tf, core::RenderSettings{}).render(view);
}
}  // namespace

TEST(StreamingConcurrency, MovingViewWithACacheSmallerThanTheWorkingSet) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({96, 96, 80}, 3, {400, 400, 400}, 12.0);
    core::BuildOptions build;
    build.brickSize = 8;
    core::JobContext job;
    core::OctreeBuilder(build).build(phantom, dir.file("p.hvo"), job);
    const auto r = core::OctreeReader::open(dir.file("p.hvo"));
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", r->geometry().valueMin, r->geometry().valueMax,
                                                   1.0, 0.0, 1.0);
    const std::size_t brickBytes = std::size_t(r->brickEdge()) * r->brickEdge() * r->brickEdge() * 2;

    core::BrickCache small(brickBytes * 16);
    core::BrickLoader loader(*r, small, 3);
    core::WorkingSetOptions opt;
    opt.uploadBytesPerFrame = brickBytes * 12;  // the pool fills over many frames, as on a GPU
    core::WorkingSet ws(*r, small, loader, opt);
    std::size_t largestCut = 0;
    for (int frame = 0; frame < 90; ++frame) {  // the loader works while the next frame is cut
        ws.update({orbitView(*r, frame * 4.0)}, tf);
        largestCut = std::max(largestCut, ws.stats().cutNodes);
        EXPECT_LE(small.bytes(), small.budget()) << "frame " << frame;
        if (frame % 15 == 0) (void)core::CpuRayCaster(*r, ws.index(), ws.slotData(), tf, {}).render(orbitView(*r, 0));
    }
    EXPECT_GT(largestCut, 16u) << "the working set must outgrow the cache for this test to mean anything";
    const auto final = orbitView(*r, 89 * 4.0);
    const auto moved = settledImage(*r, ws, final, tf);
    EXPECT_TRUE(loader.errors().empty());

    core::BrickCache roomy(1u << 30);
    core::BrickLoader calm(*r, roomy, 1);
    core::WorkingSet still(*r, roomy, calm, core::WorkingSetOptions{});
    const auto reference = settledImage(*r, still, final, tf);
    ASSERT_EQ(moved.rgba.size(), reference.rgba.size());
    double worst = 0;
    for (std::size_t i = 0; i < moved.rgba.size(); ++i)
        worst = std::max(worst, double(glm::length(moved.rgba[i] - reference.rgba[i])));
    EXPECT_LT(worst, 1e-5) << "the cut a moving view leaves must render as a still view's does";
}
