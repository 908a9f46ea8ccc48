// The crop box: millimetres to fractions (and refusals in words), the working set loading
// nothing outside the box, and a cropped render equal to the render of the same sub-volume cut
// out by hand (its own octree, its origin moved to the box's first voxel) from the same camera.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/base/Error.h"
#include "core/reference/CpuRayCaster.h"
#include "core/volume/CropBox.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/OctreeScene.h"

using namespace hvx;

namespace {
using test::errorOf;

/// A tilted, anisotropic volume of smooth values (the phantom's), held in memory.
test::MemoryVoxelSource phantom(std::array<std::uint32_t, 3> dims) {
    core::PhantomVoxelSource p(dims, 11);
    core::VolumeGeometry g = p.geometry();
    g.spacing = {0.8, 1.1, 1.5};
    const double c = std::cos(0.3), s = std::sin(0.3);
    g.direction = glm::dmat3(glm::dvec3(c, s, 0), glm::dvec3(-s, c, 0), glm::dvec3(0, 0, 1));
    g.origin = {-20.0, 13.0, 7.0};
    test::DenseVolume v;
    v.dims = dims;
    v.values.resize(std::size_t(dims[0]) * dims[1] * dims[2]);
    std::vector<std::int16_t> slice(static_cast<std::size_t>(dims[0]) * dims[1]);
    for (std::uint32_t k = 0; k < dims[2]; ++k) {
        p.readSlices(k, 1, slice.data());
        for (std::size_t i = 0; i < slice.size(); ++i) v.values[k * slice.size() + i] = slice[i];
    }
    return test::MemoryVoxelSource(g, v);
}

core::TransferFunction tfOf(const test::OctreeScene& scene) {
    const auto& g = scene.reader->geometry();
    return core::TransferFunction::preset("ct-soft-tissue", g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                          scene.ws->space().minSpacing);
}
}  // namespace

TEST(CropBox, MillimetresBecomeFractionsAndBadBoxesAreRefused) {
    const std::array<std::uint32_t, 3> dims{100, 50, 20};
    const glm::dvec3 spacing(0.5, 2.0, 3.0);  // 50 x 100 x 60 mm
    const auto b = core::CropBox::fromMillimetres({10, -5, 30}, {40, 100, 90}, dims, spacing);
    EXPECT_DOUBLE_EQ(b.min.x, 0.2);
    EXPECT_DOUBLE_EQ(b.max.x, 0.8);
    EXPECT_DOUBLE_EQ(b.min.y, 0.0) << "a face beyond the volume is clamped to it";
    EXPECT_DOUBLE_EQ(b.max.z, 1.0);
    const auto mm = b.millimetres(dims, spacing);
    EXPECT_DOUBLE_EQ(mm[0].x, 10.0);
    EXPECT_DOUBLE_EQ(mm[1].x, 40.0);
    EXPECT_FALSE(b.whole());
    EXPECT_TRUE(core::CropBox{}.whole());
    EXPECT_NE(errorOf([&] { core::CropBox::fromMillimetres({40, 0, 0}, {10, 100, 60}, dims, spacing); }).find("inside out along i"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { core::CropBox::fromMillimetres({0, 0, 0}, {50, 1, 60}, dims, spacing); }).find("thinner than a voxel along j"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { core::CropBox::fromMillimetres({0, 0, 70}, {50, 100, 90}, dims, spacing); }).find("outside the volume along k"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { core::CropBox::fromMillimetres({0, 0, NAN}, {50, 100, 60}, dims, spacing); }).find("numbers"),
              std::string::npos);
}

TEST(CropBox, TheWorkingSetLoadsNothingOutsideIt) {
    auto src = phantom({96, 80, 64});
    test::OctreeScene scene(src);
    const auto tf = tfOf(scene);
    const auto view = core::View::orbit(scene.centre(), 220.0, 30, 20, 512, 512);  // level 0 everywhere
    scene.ws->converge({view}, tf, {}, 64);
    const std::size_t whole = scene.ws->cut().size();
    core::WorkingSetOptions opt = scene.ws->options();
    opt.crop.min = {0.25, 0.0, 0.5};
    opt.crop.max = {0.75, 0.5, 1.0};
    core::WorkingSet ws(*scene.reader, *scene.cache, *scene.loader, opt);
    ws.converge({view}, tf, {}, 64);
    const auto& space = ws.space();
    std::size_t outside = 0;
    for (auto id : ws.cut()) {
        const auto& n = scene.reader->nodes()[id];
        const double size = std::ldexp(1.0, -(scene.reader->levelCount() - 1 - n.level));
        const glm::dvec3 lo = glm::dvec3(n.x, n.y, n.z) * size, hi = lo + size;
        for (int a = 0; a < 3; ++a)
            outside += hi[a] <= opt.crop.min[a] * space.extent[a] || lo[a] >= opt.crop.max[a] * space.extent[a];
    }
    std::printf("cut nodes: %zu for the whole volume, %zu for a box of 1/8 of it\n", whole, ws.cut().size());
    EXPECT_EQ(outside, 0u) << "a node outside the crop box is in the cut";
    // 18 level-0 bricks of 32 voxels hold the volume; 6 of them meet the box.
    EXPECT_LE(ws.cut().size() * 3, whole) << "the box holds an eighth of the volume";
}

TEST(CropBox, CroppedRenderEqualsTheSubVolumeCutByHand) {
    const std::array<std::uint32_t, 3> dims{96, 80, 64};
    auto src = phantom(dims);
    test::OctreeScene scene(src);
    // The box: voxels i 24..71, j 0..39, k 16..63 (faces half a voxel outside their centres).
    const std::array<std::uint32_t, 3> first{24, 0, 16}, count{48, 40, 48};
    const auto& g = src.geometry();
    glm::dvec3 lowMm, highMm;
    for (int a = 0; a < 3; ++a) {
        lowMm[a] = double(first[std::size_t(a)]) * g.spacing[a];
        highMm[a] = double(first[std::size_t(a)] + count[std::size_t(a)]) * g.spacing[a];
    }
    core::RenderSettings rs;
    rs.crop = core::CropBox::fromMillimetres(lowMm, highMm, dims, g.spacing);
    // By hand: those voxels as a volume of their own, its first voxel where it was.
    test::DenseVolume cut;
    cut.dims = count;
    for (std::uint32_t k = 0; k < count[2]; ++k)
        for (std::uint32_t j = 0; j < count[1]; ++j)
            for (std::uint32_t i = 0; i < count[0]; ++i)
                cut.values.push_back(src.values().values[((std::size_t(k + first[2]) * dims[1] + j + first[1]) * dims[0]) +
                                                         i + first[0]]);
    core::VolumeGeometry cg = g;
    cg.origin = g.origin + g.direction * (glm::dvec3(first[0], first[1], first[2]) * g.spacing);
    test::MemoryVoxelSource cutSource(cg, cut);
    test::OctreeScene byHand(cutSource);
    const auto tf = tfOf(scene);  // the same transfer function for both (the whole volume's range)
    double worst = 1e9;
    for (const auto& [az, el] : std::vector<std::pair<double, double>>{{30, 20}, {200, -35}, {90, 80}}) {
        const auto view = core::View::orbit(scene.centre(), 220.0, az, el, 160, 160);
        scene.ws->options().crop = rs.crop;
        scene.ws->converge({view}, tf, {}, 32);
        byHand.ws->converge({view}, tf, {}, 32);
        const auto a = core::CpuRayCaster(*scene.reader, scene.ws->index(), scene.ws->slotData(), tf, rs).render(view);
        const auto b = core::CpuRayCaster(*byHand.reader, byHand.ws->index(), byHand.ws->slotData(), tf, {}).render(view);
        double se = 0.0, lit = 0.0;
        for (std::size_t p = 0; p < a.rgba.size(); ++p) {
            const glm::vec4 d = a.rgba[p] - b.rgba[p];
            se += double(d.r * d.r + d.g * d.g + d.b * d.b) / 3.0;
            lit += b.rgba[p].a > 0.05f;
        }
        const double psnr = 10.0 * std::log10(1.0 / std::max(1e-12, se / double(a.rgba.size())));
        std::printf("view az %g el %g: cropped vs cut by hand %.1f dB (%.0f pixels drawn)\n", az, el, psnr, lit);
        EXPECT_GT(lit, 2000.0) << "the cut-out block shows";
        worst = std::min(worst, psnr);
    }
    // The two differ only where a ray meets a face: the cropped volume interpolates across it
    // with the voxels beyond, the cut one repeats its edge voxel.
    // Measured 41.8 dB at worst (az 30, el 20).
    EXPECT_GT(worst, 38.0);
}
