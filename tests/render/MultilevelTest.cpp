// Multilevel sampling (thesis §3.2.2, Fig. 3.6): where a cut puts bricks of different levels side
// by side, each sample blends the two levels around the cut's level field there (quadrilinear),
// so the levels meet without a seam. Cuts seen edge-on in average (X-ray) mode: with multilevel
// sampling the column where the levels meet jumps no more than any column inside a brick
// (without it, on the ramps, it jumps more). The left half of the volume at full resolution and
// the right half one level coarser, on a ramp with a ripple finer than the coarse level and on the
// phantom; and a ramp whose right half is one level coarser below y = 1/2 and two above (a leaf
// two levels coarser, coarser leaves that blend themselves), and one whose right half is three
// levels coarser. GPU equals the CPU reference; a cut of one level is unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>

#include <glm/geometric.hpp>

#include "core/reference/CpuRayCaster.h"
#include "core/volume/PhantomVoxelSource.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/OctreeScene.h"
#include "tests/support/PhantomScene.h"

using namespace hvx;

namespace {
/// Voxels of 1 mm: a ramp along i (8 a voxel) with a ripple of amplitude 60, its crest at voxel
/// centre 63.5. Of period 4 voxels, the next coarser level (each sample the mean of two) all but
/// averages it away; of period 8, at the voxels' shared face i = 64, the next level keeps 0.65
/// of it and the one above none.
test::MemoryVoxelSource rippledRamp(std::array<std::uint32_t, 3> dims = {128, 64, 64}, double period = 4.0) {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Float32;
    g.dims = dims;
    g.valueMin = -60;
    g.valueMax = 1076;
    return test::MemoryVoxelSource(g, test::generatedVolume(g.dims, [period](std::uint32_t i, std::uint32_t, std::uint32_t) {
                                       return 8.0 * i + 60.0 * std::cos(2.0 * M_PI * (i - 63.5) / period);
                                   }));
}

/// The view and what each of its columns sees: looking along the octree's z axis (the level
/// face, octree x = 1/2, edge-on), 0.25 of the finest voxel a pixel.
struct EdgeOn {
    core::View view;
    std::vector<double> octreeX;  // per column, the octree x of its ray
};

EdgeOn edgeOn(const test::OctreeScene& s, int width) {
    const auto& space = s.ws->space();
    const glm::dmat3 m(space.octreeToPatient);
    const double voxelMm = space.voxelSize(0);
    EdgeOn e;
    e.view.model = core::View::Model::Orthographic;
    e.view.target = s.centre();
    e.view.eye = e.view.target - 400.0 * glm::normalize(m * glm::dvec3(0, 0, 1));
    e.view.up = glm::normalize(m * glm::dvec3(0, 1, 0));
    const double pixel = 0.25 * voxelMm;
    e.view.width = width;
    e.view.height = 32;
    e.view.orthoHeight = pixel * e.view.height;
    const glm::dvec3 right = glm::normalize(glm::cross(e.view.target - e.view.eye, e.view.up));
    for (int c = 0; c < width; ++c) {
        const glm::dvec3 p = e.view.target + right * ((c + 0.5 - width / 2.0) * pixel);
        e.octreeX.push_back((space.patientToOctree * glm::dvec4(p, 1.0)).x);
    }
    return e;
}

/// Per column pair (c, c + 1): the mean |difference| of their grey values over the rows.
std::vector<double> columnJumps(const core::RenderImage& img) {
    std::vector<double> j(std::size_t(img.width - 1), 0.0);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x + 1 < img.width; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(img.width) + std::size_t(x);
            j[std::size_t(x)] += std::abs(double(img.rgba[i + 1].r) - double(img.rgba[i].r)) / img.height;
        }
    return j;
}

struct Seam {
    double face = 0, inside = 0;  // the largest jump at the level face, and inside any brick
};

/// The jumps across the level face (octree x = 1/2) and the largest between two columns at least
/// 4 pixels from any brick face of the finer level (octree x a multiple of 1/4 at 32-voxel
/// bricks of a 128-voxel root) and inside the volume.
Seam seam(const core::RenderImage& img, const EdgeOn& e, double brickOctree, double extentX) {
    const auto jumps = columnJumps(img);
    const double pixelOctree = std::abs(e.octreeX[1] - e.octreeX[0]);
    Seam s;
    for (std::size_t c = 0; c < jumps.size(); ++c) {
        const double a = e.octreeX[c], b = e.octreeX[c + 1];
        if ((a - 0.5) * (b - 0.5) <= 0.0) {
            s.face = std::max(s.face, jumps[c]);
            continue;
        }
        const double mid = 0.5 * (a + b);
        const double nearestFace = std::round(mid / brickOctree) * brickOctree;
        if (std::abs(mid - nearestFace) < 4.0 * pixelOctree || mid < 4.0 * pixelOctree || mid > extentX - 4.0 * pixelOctree)
            continue;
        s.inside = std::max(s.inside, jumps[c]);
    }
    return s;
}

/// Accuracy for a cut of two levels: the finest level where the octree x < 1/2, one level coarser beyond.
core::AccuracyFunction splitAccuracy(const test::OctreeScene& s) {
    const auto space = s.ws->space();
    const double voxel = space.voxelSize(0);
    return [space, voxel](const core::View&, const glm::dvec3& p) {
        return (space.patientToOctree * glm::dvec4(p, 1.0)).x < 0.5 ? 0.5 * voxel : 2.5 * voxel;
    };
}

struct Renders {
    core::RenderImage gpuOff, gpuOn, cpuOff, cpuOn;
};

Renders renderBoth(const test::OctreeScene& s, const core::TransferFunction& tf, core::RenderSettings rs,
                   const core::View& view) {
    render::GpuRayCaster gpu;
    Renders r;
    rs.multilevel = false;
    r.gpuOff = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, rs, view);
    r.cpuOff = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), tf, rs).render(view);
    rs.multilevel = true;
    r.gpuOn = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, rs, view);
    r.cpuOn = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), tf, rs).render(view);
    return r;
}

/// Checks the cut holds levels 0 to `coarsest`, and that the level face (octree x = 1/2) shows no
/// seam with multilevel sampling, on the GPU and the CPU reference, and a smaller jump than
/// without it; `seamWithout`: without it, the face jumps more than anything inside a brick (on
/// smooth data). `brick`: the finest level's brick, in octree units.
void expectNoSeam(const char* name, const test::OctreeScene& s, const core::TransferFunction& tf,
                  const core::RenderSettings& rs, const EdgeOn& e, bool seamWithout, int coarsest = 1, double brick = 0.25) {
    ASSERT_EQ(s.ws->stats().finestLevel, 0);
    ASSERT_EQ(s.ws->stats().coarsestLevel, coarsest);
    const auto r = renderBoth(s, tf, rs, e.view);
    const double extentX = s.ws->space().extent.x;
    const Seam gpuOff = seam(r.gpuOff, e, brick, extentX), gpuOn = seam(r.gpuOn, e, brick, extentX);
    const Seam cpuOff = seam(r.cpuOff, e, brick, extentX), cpuOn = seam(r.cpuOn, e, brick, extentX);
    std::printf("%s: largest jump at the level face / inside a brick: one level a leaf %.4f / %.4f (GPU), %.4f / %.4f "
                "(CPU); multilevel %.4f / %.4f (GPU), %.4f / %.4f (CPU)\n",
                name, gpuOff.face, gpuOff.inside, cpuOff.face, cpuOff.inside, gpuOn.face, gpuOn.inside, cpuOn.face,
                cpuOn.inside);
    if (seamWithout) {
        EXPECT_GT(gpuOff.face, gpuOff.inside) << "the cut shows no seam to remove";
        EXPECT_GT(cpuOff.face, cpuOff.inside);
    }
    EXPECT_LT(gpuOn.face, 0.5 * gpuOff.face);
    EXPECT_LT(cpuOn.face, 0.5 * cpuOff.face);
    EXPECT_LE(gpuOn.face, gpuOn.inside) << "a seam where the levels meet";
    EXPECT_LE(cpuOn.face, cpuOn.inside);
    const double db = test::psnr(r.cpuOn, r.gpuOn);
    std::printf("%s: multilevel GPU vs CPU %.1f dB (one level a leaf: %.1f dB)\n", name, db, test::psnr(r.cpuOff, r.gpuOff));
    EXPECT_GT(db, 80.0);
}

/// The seam test in average (X-ray) mode: the scene's cut refined to two levels for an edge-on
/// view `width` pixels wide, then expectNoSeam.
void expectNoSeamInAverage(const char* name, const test::OctreeScene& s, const core::TransferFunction& tf, int width,
                           bool seamWithout) {
    const auto e = edgeOn(s, width);
    s.ws->converge({e.view}, tf, splitAccuracy(s));
    render::EglOffscreenContext ctx;
    core::RenderSettings rs;
    rs.mode = core::RenderSettings::Mode::Average;
    expectNoSeam(name, s, tf, rs, e, seamWithout);
}

/// A 128³ rippled ramp (`period`) in bricks of `brickSize`, its cut refined for an edge-on view by
/// `accuracy` (finest voxels, by octree position) to levels 0 to `coarsest`: every leaf reaches
/// the levels its field needs (none clamped, some past the parent), then expectNoSeam.
void expectNoSeamAcrossLevels(const char* name, std::uint32_t brickSize, double period, int coarsest,
                              std::function<double(const glm::dvec3&)> accuracy) {
    auto source = rippledRamp({128, 128, 128}, period);
    core::BuildOptions options;
    options.brickSize = brickSize;
    test::OctreeScene s(source, options);
    const core::TransferFunction tf({{-60, glm::dvec4(1, 1, 1, 0.01)}, {1076, glm::dvec4(1, 1, 1, 0.01)}}, -60, 1076);
    const auto e = edgeOn(s, 512);
    const auto space = s.ws->space();
    const double voxel = space.voxelSize(0);
    s.ws->converge({e.view}, tf, [space, voxel, accuracy](const core::View&, const glm::dvec3& p) {
        return accuracy(glm::dvec3(space.patientToOctree * glm::dvec4(p, 1.0))) * voxel;
    });
    const auto& idx = s.ws->index();
    std::size_t pastParent = 0;
    float farthest = 0.0f;
    for (const auto& lv : idx.levels) {
        pastParent += lv.ancestors[1] != core::SpatialIndex::kNone;
        for (float f : lv.coarser) farthest = std::max(farthest, f);
    }
    std::printf("%s: %zu leaves blend, %zu of them past their parent, %zu clamped; the field reaches %.2f levels up\n", name,
                idx.blendingLeaves, pastParent, idx.steepLeaves, farthest);
    EXPECT_GT(pastParent, 0u);
    EXPECT_EQ(idx.steepLeaves, 0u);
    EXPECT_EQ(farthest, float(coarsest)) << "the finest leaves meet the coarsest";
    render::EglOffscreenContext ctx;
    core::RenderSettings rs;
    rs.mode = core::RenderSettings::Mode::Average;
    expectNoSeam(name, s, tf, rs, e, true, coarsest, double(brickSize) / 128.0);
}
}  // namespace

TEST(Multilevel, ARampMeetsItsCoarserLevelWithoutASeam) {
    auto source = rippledRamp();
    test::OctreeScene s(source);
    const core::TransferFunction tf({{-60, glm::dvec4(1, 1, 1, 0.01)}, {1076, glm::dvec4(1, 1, 1, 0.01)}}, -60, 1076);
    expectNoSeamInAverage("rippled ramp", s, tf, 512, true);
}

TEST(Multilevel, ARampMeetsALeafTwoLevelsCoarserAndABlendingNeighbourWithoutASeam) {
    // 128³ voxels in bricks of 16 (four levels). The left half at full resolution; on the right,
    // below octree y = 1/2 one level coarser, above it two. Where the face (x = 1/2) meets the
    // upper right, the finer leaves' field reaches two levels (their grandparent's); below, the
    // coarser leaves themselves blend towards the level above them near y = 1/2, and the finer
    // leaves across the face follow (hanging corners). The view's rows straddle y = 1/2. A blend
    // reaching one level only (the finer leaves' parent) leaves a seam: the ripple's 0.65 of the
    // middle level against none of the top one.
    expectNoSeamAcrossLevels("three-level ramp", 16, 8.0, 2, [](const glm::dvec3& o) {
        return o.x < 0.5 ? 0.5 : o.y < 0.5 ? 2.5 : 5.0;
    });
}

TEST(Multilevel, ARampMeetsALeafThreeLevelsCoarserWithoutASeam) {
    // 128³ voxels in bricks of 8 (five levels). The left half at full resolution, the right half
    // three levels coarser (8 voxels a sample): at the face, the finer leaves' field reaches
    // their great-grandparent. A ripple of period 16: the level 4 voxels a sample keeps 0.64 of
    // it, the level 8 voxels a sample samples it at its zero crossings (none left). A blend that
    // stopped at the grandparent would leave that seam.
    expectNoSeamAcrossLevels("four-level ramp", 8, 16.0, 3, [](const glm::dvec3& o) { return o.x < 0.5 ? 0.5 : 10.0; });
}

TEST(Multilevel, ThePhantomMeetsItsCoarserLevelWithoutASeam) {
    test::PhantomScene s;
    // The phantom's own edges and noise jump more than the seam does (0.003 against 0.06
    // measured): the seam is not the largest jump even without multilevel sampling, but it shrinks.
    expectNoSeamInAverage("phantom (average)", s, s.tf, 384, false);
}

TEST(Multilevel, GpuEqualsTheCpuReferenceInDvrAndOneLevelIsUnchanged) {
    test::PhantomScene s;
    const auto& tf = s.tf;
    const auto& view = s.view;
    render::EglOffscreenContext ctx;
    core::RenderSettings rs;
    // A cut of two levels, seen in DVR with shading: samples and gradients blend.
    s.ws->converge({view}, tf, splitAccuracy(s));
    ASSERT_EQ(s.ws->stats().coarsestLevel, 1);
    std::size_t blended = 0;
    for (const auto& lv : s.ws->index().levels) blended += lv.blends;
    EXPECT_GT(blended, 0u);
    const auto mixed = renderBoth(s, tf, rs, view);
    const double dvrDb = test::psnr(mixed.cpuOn, mixed.gpuOn), change = test::psnr(mixed.cpuOn, mixed.cpuOff);
    std::printf("phantom DVR, two levels: %zu leaves blend with their parent; multilevel GPU vs CPU %.1f dB, "
                "against one level a leaf %.1f dB\n",
                blended, dvrDb, change);
    EXPECT_GT(dvrDb, 80.0);
    EXPECT_LT(change, 80.0) << "multilevel sampling changes the leaves beside coarser ones";
    // With the detail shading too: the blended field's gradient against the parent level's.
    auto detailed = rs;
    detailed.normalUnsharp = 2.0;
    detailed.exaggeratedShading = 0.5;
    const auto both = renderBoth(s, tf, detailed, view);
    const double detailDb = test::psnr(both.cpuOn, both.gpuOn);
    std::printf("phantom DVR, two levels, with unsharp masking 2 and exaggerated shading 0.5: multilevel GPU vs CPU %.1f dB\n",
                detailDb);
    EXPECT_GT(detailDb, 80.0);
    // One level everywhere: no leaf blends, the image is bitwise the one without multilevel sampling.
    auto one = s.ws->options();
    one.finestLevel = 1;
    s.ws->options() = one;
    s.ws->converge({view}, tf);
    ASSERT_EQ(s.ws->stats().finestLevel, 1);
    ASSERT_EQ(s.ws->stats().coarsestLevel, 1);
    for (const auto& lv : s.ws->index().levels) EXPECT_EQ(lv.blends, 0u);
    EXPECT_EQ(s.ws->index().blendingLeaves, 0u);
    const auto uniform = renderBoth(s, tf, rs, view);
    EXPECT_EQ(test::psnr(uniform.gpuOn, uniform.gpuOff), 99.0);
    EXPECT_EQ(test::psnr(uniform.cpuOn, uniform.cpuOff), 99.0);
}
