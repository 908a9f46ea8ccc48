// The GPU's split-voxel variant (HVX_SPLIT, raycast_split.glsl) against its CPU reference
// (CpuRayCaster over the same working set, core/reference/SplitCellMarch.h): a two-material
// sphere built as split-voxel octrees of 8-bit and signed 16-bit intensities and of an 8-bit
// label map, seen at full resolution and through the root alone, shaded and unshaded. Both draw
// the same image, count the same rays per node, and unshaded the GPU shows no colour that
// neither material has at any level.
#include <gtest/gtest.h>

#include <cstdio>
#include <numeric>

#include <glm/geometric.hpp>

#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/octree/SplitVoxelOctreeBuilder.h"
#include "core/reference/CpuRayCaster.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickCells.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/SplitVoxelScene.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
/// The two-material sphere as a split-voxel octree `path` of bricks of `brickSize` cells (16:
/// cells 64³, levels of 4³, 2³ and 1 brick), its air `air`, the material threshold 20.
std::unique_ptr<core::OctreeReader> splitSphere(const std::string& path, core::VolumeGeometry g, std::uint32_t brickSize = 16,
                                                double air = 0.0) {
    auto volume = test::twoMaterialSphere();
    for (auto& v : volume.values)
        if (v == 0.0) v = air;
    test::MemoryVoxelSource source(g, std::move(volume));
    core::BuildOptions b;
    b.brickSize = brickSize;
    core::SplitVoxelOptions o;
    o.threshold = 20.0;
    core::JobContext job;
    core::SplitVoxelOctreeBuilder(b, o).build(source, path, job);
    return core::OctreeReader::open(path, true);
}

struct Case {
    const char* name;
    core::ScalarType type;
    bool labels;
    double air;  // the value outside the sphere (negative: the signed path's sign extension)
};
}  // namespace

TEST(SplitVoxelGpu, GpuEqualsTheCpuReferenceForEveryStoredType) {
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const auto tf = test::threeColours();
    for (const Case& c : {Case{"8-bit intensities", core::ScalarType::UInt8, false, 0.0},
                          Case{"signed 16-bit intensities", core::ScalarType::Int16, false, -50.0},
                          Case{"8-bit label map", core::ScalarType::UInt8, true, 0.0}}) {
        core::VolumeGeometry g;
        g.scalarType = c.type;
        g.isLabel = c.labels;
        g.valueMin = c.air;
        g.valueMax = 200.0;
        g.spacing = {0.9, 1.1, 1.3};
        test::TempDir dir;
        const auto reader = splitSphere(dir.file("s.hvo"), g, 16, c.air);
        ASSERT_EQ(reader->levelCount(), 3);
        const auto space = core::OctreeSpace::of(reader->geometry(), reader->brickSize(), reader->levelCount());
        const auto view = core::View::orbit(space.centre(), 350.0, -40.0, 25.0, 160, 160);
        for (const int level : {0, 2})
            for (const bool shading : {false, true}) {
                core::RenderSettings rs;
                rs.shading = shading;
                rs.countRays = true;
                core::BrickCache cache(std::size_t(1) << 28);
                core::BrickLoader loader(*reader, cache);
                core::WorkingSetOptions wo;
                wo.voxelsPerPixel = level == 0 ? 1e-6 : 1e9;
                wo.cpuMirror = true;
                core::WorkingSet ws(*reader, cache, loader, wo);
                ws.converge({view}, tf);
                ASSERT_EQ(ws.stats().finestLevel, level);
                const auto cpu = core::CpuRayCaster(*reader, ws.index(), ws.slotData(), tf, rs).render(view);
                const auto gl = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, rs, view);
                int lit = 0;
                for (const auto& p : gl.rgba) lit += p.a > 0.5f;
                const double db = test::psnr(cpu, gl);
                const auto sum = [](const std::vector<std::uint32_t>& v) {
                    return std::accumulate(v.begin(), v.end(), std::uint64_t(0));
                };
                const std::uint64_t raysCpu = sum(cpu.rayCounts), raysGpu = sum(gl.rayCounts);
                std::printf("%s, level %d, %s: GPU vs CPU %.1f dB, %d pixels covered, rays counted %llu (CPU %llu), "
                            "GPU pixels of neither colour %d\n",
                            c.name, level, shading ? "shaded" : "unshaded", db, lit, (unsigned long long)raysGpu,
                            (unsigned long long)raysCpu, test::foreignPixels(gl));
                EXPECT_GT(lit, 2000) << c.name;
                EXPECT_GT(db, 45.0) << c.name << " level " << level;
                ASSERT_EQ(gl.rayCounts.size(), cpu.rayCounts.size());
                EXPECT_NEAR(double(raysGpu), double(raysCpu), 0.01 * double(raysCpu)) << c.name;
                if (!shading) EXPECT_EQ(test::foreignPixels(gl), 0) << c.name << " level " << level;  // (highlights are white)
                // The blocks the transfer function hides (air) are crossed in one step: the same image.
                core::RenderSettings every = rs;
                every.skipEmptyCells = false;
                EXPECT_GT(test::psnr(gpu.render(*reader, ws.index(), ws.slotBricks(), tf, every, view), gl), 80.0) << c.name;
            }
        // Hidden blocks exist, and a block's range holds every value of its cells.
        std::size_t hidden = 0, blocks = 0;
        for (std::uint32_t n = 0; n < reader->nodes().size(); ++n) {
            const auto brick = reader->readBrick(n);
            const auto cells = core::BrickCells::ofSplit(brick);
            const std::uint64_t bits = cells.visible(tf, c.labels);
            for (std::uint32_t z = 0; z < brick.edge; ++z)
                for (std::uint32_t y = 0; y < brick.edge; ++y)
                    for (std::uint32_t x = 0; x < brick.edge; ++x) {
                        const auto v = brick.cell(x, y, z);
                        const auto& r = cells.ranges[x / 4 + 4 * (y / 4 + 4 * (z / 4))];
                        ASSERT_TRUE(r.x <= std::min(v.front, v.back) && std::max(v.front, v.back) <= r.y);
                    }
            for (int block = 0; block < 64; ++block, ++blocks) hidden += !(bits >> block & 1u);
        }
        std::printf("%s: %zu of %zu blocks hidden by the transfer function\n", c.name, hidden, blocks);
        EXPECT_GT(hidden, blocks / 4) << c.name;
    }
}

// A split-voxel octree and a brick of the wrong kind are refused in words: modes other than
// DVR, the illustrative tools and fusion are not drawn over split-voxels yet.
TEST(SplitVoxelGpu, WhatTheVariantDoesNotDrawIsRefusedInWords) {
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.valueMax = 200.0;
    test::TempDir dir;
    const auto reader = splitSphere(dir.file("s.hvo"), g, 32);
    const auto tf = test::threeColours();
    const auto space = core::OctreeSpace::of(reader->geometry(), reader->brickSize(), reader->levelCount());
    const auto view = core::View::orbit(space.centre(), 350.0, 0.0, 0.0, 32, 32);
    core::BrickCache cache(std::size_t(1) << 26);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSet ws(*reader, cache, loader, core::WorkingSetOptions{});
    ws.converge({view}, tf);
    core::RenderSettings mip;
    mip.mode = core::RenderSettings::Mode::Mip;
    try {
        gpu.render(*reader, ws.index(), ws.slotBricks(), tf, mip, view);
        ADD_FAILURE() << "MIP over split-voxels was not refused";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("split-voxel octree is drawn in DVR"), std::string::npos) << e.what();
    }
    // The same caster then draws it in DVR.
    const auto img = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, core::RenderSettings{}, view);
    int lit = 0;
    for (const auto& p : img.rgba) lit += p.a > 0.5f;
    EXPECT_GT(lit, 100);
}

namespace {
/// A working set over `reader` holding its level `level` wherever the view reaches it.
struct LevelScene {
    core::BrickCache cache{std::size_t(1) << 28};
    core::BrickLoader loader;
    core::WorkingSet ws;
    LevelScene(const core::OctreeReader& reader, int level, const core::View& view, const core::TransferFunction& tf)
        : loader(reader, cache), ws(reader, cache, loader, [&] {
              core::WorkingSetOptions o;
              o.voxelsPerPixel = 1e-6;
              o.finestLevel = level;
              return o;
          }()) {
        ws.converge({view}, tf);
    }
};
}  // namespace

// The thesis's Fig. 4.6 on the GPU: one octree level (voxels of 4) drawn with trilinear and
// nearest reconstruction from the plain octree and with split-voxels (cells of 4). The coarse
// level's averaged voxels hold values between the two materials, so trilinear and nearest both
// show the colour of neither; split-voxels show none. Nearest on the GPU equals its CPU reference.
TEST(SplitVoxelGpu, OneLevelThreeReconstructionsAsTheThesisFigure) {
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.valueMax = 200.0;
    test::MemoryVoxelSource source(g, test::twoMaterialSphere());
    test::TempDir dir;
    core::BuildOptions b;
    b.brickSize = 16;
    core::JobContext job;
    core::OctreeBuilder(b).build(source, dir.file("plain.hvo"), job);
    const auto plain = core::OctreeReader::open(dir.file("plain.hvo"));
    const auto split = splitSphere(dir.file("split.hvo"), g);
    const auto tf = test::threeColours();
    const auto space = core::OctreeSpace::of(plain->geometry(), plain->brickSize(), plain->levelCount());
    const auto view = core::View::orbit(space.centre(), 350.0, -40.0, 25.0, 160, 160);
    core::RenderSettings rs;
    rs.shading = false;
    LevelScene p(*plain, 2, view, tf), s(*split, 1, view, tf);
    ASSERT_EQ(p.ws.stats().finestLevel, 2);
    ASSERT_EQ(p.ws.stats().coarsestLevel, 2);
    ASSERT_EQ(s.ws.stats().finestLevel, 1);
    ASSERT_EQ(s.ws.stats().coarsestLevel, 1);
    const auto trilinear = gpu.render(*plain, p.ws.index(), p.ws.slotBricks(), tf, rs, view);
    rs.nearest = true;
    const auto nearest = gpu.render(*plain, p.ws.index(), p.ws.slotBricks(), tf, rs, view);
    const auto nearestCpu = core::CpuRayCaster(*plain, p.ws.index(), p.ws.slotData(), tf, rs).render(view);
    const auto splitImage = gpu.render(*split, s.ws.index(), s.ws.slotBricks(), tf, rs, view);
    const double db = test::psnr(nearest, nearestCpu);
    std::printf("voxels of 4: pixels of neither material's colour: trilinear %d, nearest %d, split-voxels %d; "
                "nearest GPU vs CPU %.1f dB\n",
                test::foreignPixels(trilinear), test::foreignPixels(nearest), test::foreignPixels(splitImage), db);
    EXPECT_GT(test::foreignPixels(trilinear), 100);
    EXPECT_GT(test::foreignPixels(nearest), 100);
    EXPECT_EQ(test::foreignPixels(splitImage), 0);
    EXPECT_GT(db, 45.0);
    EXPECT_GT(test::psnr(trilinear, nearest), 10.0);  // the two reconstructions differ, yet draw the same sphere
    EXPECT_LT(test::psnr(trilinear, nearest), 60.0);
}

// The illustrative tools over split-voxels (a clip plane through the sphere and a focal probe
// on it): GPU equals the CPU reference, and the tools change the image.
TEST(SplitVoxelGpu, TheToolsDrawOverSplitVoxelsAsTheCpuReferenceDoes) {
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Int16;
    g.valueMax = 200.0;
    g.spacing = {0.9, 1.1, 1.3};
    test::TempDir dir;
    const auto reader = splitSphere(dir.file("s.hvo"), g);
    const auto tf = test::threeColours();
    const auto space = core::OctreeSpace::of(reader->geometry(), reader->brickSize(), reader->levelCount());
    const auto view = core::View::orbit(space.centre(), 350.0, -40.0, 25.0, 160, 160);
    core::BrickCache cache(std::size_t(1) << 28);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSetOptions wo;
    wo.voxelsPerPixel = 1e-6;
    core::WorkingSet ws(*reader, cache, loader, wo);
    ws.converge({view}, tf);
    core::RenderSettings plain;
    const auto without = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, plain, view);
    const glm::dvec3 centre = space.centre();
    core::ToolSet tools;
    tools.clip.enabled = true;
    tools.clip.normal = glm::dvec3(0.3, 0.2, 1.0);
    tools.clip.offset = -glm::dot(tools.clip.normal, centre);  // through the sphere's centre
    tools.focal.enabled = true;
    tools.focal.centre = centre + glm::dvec3(20.0, 0.0, 0.0);
    tools.focal.radii = glm::dvec3(25.0);
    tools.validate();
    ASSERT_NE(tools.variantBits(), 0);
    for (const bool shading : {false, true}) {
        core::RenderSettings rs;
        rs.shading = shading;
        rs.tools = tools;
        const auto gl = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, rs, view);
        const auto cpu = core::CpuRayCaster(*reader, ws.index(), ws.slotData(), tf, rs).render(view);
        const double db = test::psnr(cpu, gl), changed = test::psnr(without, gl);
        std::printf("tools over split-voxels, %s: GPU vs CPU %.1f dB; against the frame without tools %.1f dB\n",
                    shading ? "shaded" : "unshaded", db, changed);
        EXPECT_GT(db, 45.0);
        EXPECT_LT(changed, 35.0);
    }
}
