// Split-voxel rendering on the CPU (thesis §4.5.2): a sphere of two materials, seen through a
// coarse level, shows no colour that neither material has, where the product's trilinear ray
// caster at the octree level of the same voxel size shows the colour the transfer function gives
// the values between them; and the split-voxel silhouette stays near the full-resolution one
// (Hausdorff distance in pixels, reported and bounded for both).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include <filesystem>

#include "core/base/JobContext.h"
#include "core/image/ImageWriter.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/octree/SplitVoxelGrid.h"
#include "core/octree/SplitVoxelOctreeBuilder.h"
#include "core/reference/CpuRayCaster.h"
#include "core/reference/SplitVoxelRayCaster.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/SplitVoxelScene.h"
#include "tests/support/TempDir.h"

using namespace hvx;
using test::foreignPixels;
using test::threeColours;
using test::twoMaterialSphere;

namespace {
constexpr int kSize = 192;

/// The product's ray caster over a plain octree of `brickSize` bricks: at the root alone
/// (`coarse`) or at full resolution.
core::RenderImage plainRender(core::VoxelSource& source, std::uint32_t brickSize, bool coarse, const core::View& view,
                              const core::TransferFunction& tf, const core::RenderSettings& rs, int& level) {
    test::TempDir dir;
    core::BuildOptions b;
    b.brickSize = brickSize;
    core::JobContext job;
    core::OctreeBuilder(b).build(source, dir.file("plain.hvo"), job);
    const auto reader = core::OctreeReader::open(dir.file("plain.hvo"));
    core::BrickCache cache(std::size_t(1) << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSetOptions o;
    o.voxelsPerPixel = coarse ? 1e9 : 1e-6;
    core::WorkingSet ws(*reader, cache, loader, o);
    ws.converge({view}, tf);
    level = ws.stats().finestLevel;
    EXPECT_EQ(ws.stats().finestLevel, ws.stats().coarsestLevel);
    return core::CpuRayCaster(*reader, ws.index(), ws.slotData(), tf, rs).render(view);
}

/// The silhouette's pixels: covered (alpha > ½) with an uncovered 4-neighbour.
std::vector<glm::ivec2> outline(const core::RenderImage& img) {
    const auto on = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < img.width && y < img.height && img.rgba[std::size_t(y * img.width + x)].a > 0.5f;
    };
    std::vector<glm::ivec2> edge;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (on(x, y) && (!on(x - 1, y) || !on(x + 1, y) || !on(x, y - 1) || !on(x, y + 1))) edge.emplace_back(x, y);
    return edge;
}

double hausdorff(const std::vector<glm::ivec2>& a, const std::vector<glm::ivec2>& b) {
    const auto directed = [](const std::vector<glm::ivec2>& p, const std::vector<glm::ivec2>& q) {
        double worst = 0;
        for (const auto& x : p) {
            double best = 1e300;
            for (const auto& y : q) best = std::min(best, glm::length(glm::dvec2(x - y)));
            worst = std::max(worst, best);
        }
        return worst;
    };
    if (a.empty() || b.empty()) return 1e300;
    return std::max(directed(a, b), directed(b, a));
}
}  // namespace

TEST(SplitVoxelRender, CoarseLevelsKeepEachMaterialsColourAndTheSilhouette) {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Int16;
    g.valueMax = 200.0;
    test::MemoryVoxelSource source(g, twoMaterialSphere());
    const auto tf = threeColours();
    core::RenderSettings rs;
    rs.shading = false;  // colours exactly as classified: the count below is of hues alone
    const auto space = core::OctreeSpace::of(source.geometry(), 32, 3);
    const auto view = core::View::orbit(space.centre(), 350.0, 30.0, 20.0, kSize, kSize);
    int level = -1;
    const auto full = plainRender(source, 32, false, view, tf, rs, level);
    ASSERT_EQ(level, 0);
    const auto fullOutline = outline(full);
    ASSERT_GT(fullOutline.size(), 100u);
    // Trilinear interpolation makes the in-between value at every level, full resolution too
    // (the thesis's Fig. 4.1): its blue pixels here are the baseline, not a fault of a level.
    std::printf("full resolution, trilinear: %d blue pixels\n", foreignPixels(full));

    core::SplitVoxelOptions o;
    o.threshold = 20.0;
    core::JobContext job;
    auto split = core::SplitVoxelGrid::build(source, o, job);
    // Cells of 4 voxels (the octree's level 2, bricks of 32) and of 8 (level 3, bricks of 16).
    for (const auto& [brickSize, cell] : {std::pair<std::uint32_t, std::uint32_t>{32, 4}, {16, 8}}) {
        while (split.cellVoxels() < cell) split = split.coarser(o, job);
        const auto trilinear = plainRender(source, brickSize, true, view, tf, rs, level);
        ASSERT_EQ(1 << level, int(cell));
        const auto splitImage = core::SplitVoxelRayCaster(split, source.geometry(), tf, rs).render(view);
        // Kept for a look: the three renders side by side in the thesis's Fig. 4.6 order.
        const std::string artifacts = std::string(HVX_BINARY_DIR) + "/test-artifacts/split-voxels";
        std::filesystem::create_directories(artifacts);
        core::ImageWriter::writePng(trilinear, artifacts + "/trilinear-cells" + std::to_string(cell) + ".png");
        core::ImageWriter::writePng(splitImage, artifacts + "/split-cells" + std::to_string(cell) + ".png");
        if (cell == 4) core::ImageWriter::writePng(full, artifacts + "/full-resolution.png");
        const int foreignTrilinear = foreignPixels(trilinear), foreignSplit = foreignPixels(splitImage);
        const double hTrilinear = hausdorff(outline(trilinear), fullOutline), hSplit = hausdorff(outline(splitImage), fullOutline);
        std::printf("cells of %u voxels: blue pixels trilinear %d, split-voxels %d; silhouette Hausdorff distance to full "
                    "resolution: trilinear %.2f px, split-voxels %.2f px\n",
                    cell, foreignTrilinear, foreignSplit, hTrilinear, hSplit);
        EXPECT_EQ(foreignSplit, 0);
        EXPECT_GT(foreignTrilinear, 20) << "the trilinear coarse level blends the materials";
        // Measured: 2.0 px (trilinear 2.2) with cells of 4 voxels, 5.0 px (trilinear 4.5) with
        // cells of 8, the worst pixel where the seam meets the outline: a cell there holds
        // three materials and keeps two. About 1 mm a pixel here.
        EXPECT_LE(hSplit, double(cell) * 0.75);
        EXPECT_LE(hTrilinear, double(cell) * 0.75);
    }
}

// A split-voxel .hvo drawn through the working set by the CPU ray caster (leaf by leaf, each
// leaf's cells by the same DDA) gives the image the reference caster gives over the same level
// held whole: at full resolution (cells of 2 voxels) and through the root alone (cells of 8),
// unshaded and shaded.
TEST(SplitVoxelRender, AnOctreeDrawnThroughTheWorkingSetMatchesTheLevelHeldWhole) {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Int16;
    g.valueMax = 200.0;
    g.spacing = {0.9, 1.1, 1.3};
    test::MemoryVoxelSource source(g, twoMaterialSphere());
    test::TempDir dir;
    core::BuildOptions b;
    b.brickSize = 16;  // cells 64³: levels of 4³, 2³ and 1 brick
    core::SplitVoxelOptions o;
    o.threshold = 20.0;
    core::JobContext job;
    core::SplitVoxelOctreeBuilder(b, o).build(source, dir.file("s.hvo"), job);
    const auto reader = core::OctreeReader::open(dir.file("s.hvo"), true);
    ASSERT_EQ(reader->levelCount(), 3);
    std::vector<core::SplitVoxelGrid> levels{core::SplitVoxelGrid::build(source, o, job)};
    while (levels.size() < 3) levels.push_back(levels.back().coarser(o, job));
    const auto tf = threeColours();
    const auto space = core::OctreeSpace::of(reader->geometry(), reader->brickSize(), reader->levelCount());
    const auto view = core::View::orbit(space.centre(), 350.0, -40.0, 25.0, kSize, kSize);
    for (const bool shading : {false, true})
        for (const int level : {0, 2}) {
            core::RenderSettings rs;
            rs.shading = shading;
            core::BrickCache cache(std::size_t(1) << 28);
            core::BrickLoader loader(*reader, cache);
            core::WorkingSetOptions wo;
            wo.voxelsPerPixel = level == 0 ? 1e-6 : 1e9;
            core::WorkingSet ws(*reader, cache, loader, wo);
            ws.converge({view}, tf);
            ASSERT_EQ(ws.stats().finestLevel, level);
            ASSERT_EQ(ws.stats().coarsestLevel, level);
            const auto viaOctree = core::CpuRayCaster(*reader, ws.index(), ws.slotData(), tf, rs).render(view);
            const auto whole = core::SplitVoxelRayCaster(levels[std::size_t(level)], source.geometry(), tf, rs).render(view);
            double se = 0;
            int lit = 0;
            for (std::size_t i = 0; i < whole.rgba.size(); ++i) {
                const glm::vec4 e = viaOctree.rgba[i] - whole.rgba[i];
                se += double(e.r * e.r + e.g * e.g + e.b * e.b);
                lit += whole.rgba[i].a > 0.5f;
            }
            const double mse = se / (3.0 * double(whole.rgba.size()));
            const double db = mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0;
            std::printf("level %d (cells of %u voxels), %s: through the working set vs held whole %.1f dB, %d pixels covered\n",
                        level, levels[std::size_t(level)].cellVoxels(), shading ? "shaded" : "unshaded", db, lit);
            EXPECT_GT(lit, 2000);
            EXPECT_GT(db, shading ? 35.0 : 45.0);
        }
}
