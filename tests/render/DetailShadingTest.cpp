// Multilevel shading (thesis §3.2.2, Fig. 3.7): normal unsharp masking and exaggerated shading,
// on the GPU and in the CPU reference alike, in DVR and isosurface mode. Off (strength 0) the
// image is bitwise today's; on a flat boundary, where the fine and the coarse normals agree,
// there is nothing to enhance and the image stays as it was; on the phantom's organs it changes.
#include <gtest/gtest.h>

#include <cstdio>

#include <glm/geometric.hpp>

#include "core/reference/CpuRayCaster.h"
#include "core/volume/PhantomVoxelSource.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/PhantomScene.h"

using namespace hvx;

namespace {
struct Case {
    const char* name;
    double unsharp, exaggerated;
};
const Case kCases[] = {{"unsharp masking 2", 2.0, 0.0}, {"exaggerated shading 1", 0.0, 1.0}, {"both (1, 0.6)", 1.0, 0.6}};

/// 64³ CT-like values: air (-1000) on one side of an oblique plane, soft tissue (40) on the
/// other, a linear ramp of 16 voxels between (no noise): both gradients, at one and at two voxels'
/// spacing, lie wholly in the ramp and agree.
test::MemoryVoxelSource flatBoundary() {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Float32;  // not rounded to whole HU: the ramp stays exactly linear
    g.dims = {64, 64, 64};
    g.spacing = {1.5, 1.5, 1.5};
    g.modality = "CT";
    g.valueMin = -1000;
    g.valueMax = 40;
    test::DenseVolume v;
    v.dims = g.dims;
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -1.0, 0.4)), c(31.5);
    for (std::uint32_t k = 0; k < 64; ++k)
        for (std::uint32_t j = 0; j < 64; ++j)
            for (std::uint32_t i = 0; i < 64; ++i) {
                const double d = glm::dot(glm::dvec3(i, j, k) - c, n);
                v.values.push_back(d < -8 ? -1000.0 : d > 8 ? 40.0 : -1000.0 + 1040.0 * (d + 8) / 16);
            }
    return test::MemoryVoxelSource(g, v);
}
}  // namespace

TEST(DetailShading, GpuEqualsCpuAndStrengthZeroChangesNothing) {
    test::PhantomScene s;
    const auto& tf = s.tf;
    const auto& view = s.view;
    s.converge();
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    for (auto mode : {core::RenderSettings::Mode::Dvr, core::RenderSettings::Mode::Iso}) {
        core::RenderSettings plain;
        plain.mode = mode;
        plain.isoValue = 100;
        const auto cpuPlain = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), tf, plain).render(view);
        const auto gpuPlain = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, plain, view);
        std::printf("%s, plain shading: GPU vs CPU %.1f dB\n", mode == core::RenderSettings::Mode::Dvr ? "DVR" : "iso",
                    test::psnr(cpuPlain, gpuPlain));
        auto zero = plain;  // both strengths 0: no variant, today's code
        zero.normalUnsharp = 0;
        zero.exaggeratedShading = 0;
        EXPECT_FALSE(zero.detailShading());
        EXPECT_EQ(test::psnr(gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, zero, view), gpuPlain), 99.0);
        for (const auto& c : kCases) {
            auto rs = plain;
            rs.normalUnsharp = c.unsharp;
            rs.exaggeratedShading = c.exaggerated;
            ASSERT_TRUE(rs.detailShading());
            const auto cpu = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), tf, rs).render(view);
            const auto gl = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, rs, view);
            const double db = test::psnr(cpu, gl), change = test::psnr(cpu, cpuPlain);
            std::printf("%s, %s: GPU vs CPU %.1f dB; against plain shading %.1f dB\n",
                        mode == core::RenderSettings::Mode::Dvr ? "DVR" : "iso", c.name, db, change);
            // Isosurface: the crossing found by bisection lies a float rounding apart on the two
            // (plain shading agrees less there too), and the enhancement amplifies the normal's
            // change with position; the bar follows plain shading's agreement.
            EXPECT_GT(db, mode == core::RenderSettings::Mode::Dvr ? 80.0 : test::psnr(cpuPlain, gpuPlain) - 10.0) << c.name;
            EXPECT_LT(change, 45.0) << c.name << ": the organs' detail is enhanced";
        }
    }
}

TEST(DetailShading, AFlatBoundaryHasNothingToEnhance) {
    auto source = flatBoundary();
    test::OctreeScene s(source);
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", -1000, 40, 1, 0, s.ws->space().minSpacing);
    const auto view = core::View::orbit(s.centre(), 250.0, 20.0, 10.0, 96, 96);
    s.ws->converge({view}, tf);
    core::RenderSettings plain;
    plain.mode = core::RenderSettings::Mode::Iso;
    plain.isoValue = -480;
    plain.crop.min = glm::dvec3(0.15);  // the plane away from the volume's faces, where the wider stencil is clamped
    plain.crop.max = glm::dvec3(0.85);
    const auto before = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), tf, plain).render(view);
    std::size_t hit = 0;
    for (const auto& p : before.rgba) hit += p.a > 0.5f;
    ASSERT_GT(hit, 1500u) << "the plane fills much of the view";
    for (const auto& c : kCases) {
        auto rs = plain;
        rs.normalUnsharp = c.unsharp;
        rs.exaggeratedShading = c.exaggerated;
        const auto after = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), tf, rs).render(view);
        const double db = test::psnr(after, before);
        std::printf("flat boundary, %s: %.1f dB from plain shading\n", c.name, db);
        EXPECT_GT(db, 50.0) << c.name << " changed a surface without detail";
    }
}

// The coarser scale is the parent level's gradient (thesis §3.2.2: the multilevel gradients),
// wherever the working set keeps a leaf's parent resident; an index not linked to parents falls
// back to the leaf's own brick at twice its spacing. Both agree with the CPU reference, and the
// two coarser scales draw different images.
TEST(DetailShading, TheCoarserScaleIsTheParentLevelsGradient) {
    test::PhantomScene s;
    const auto& tf = s.tf;
    const auto& view = s.view;
    s.converge();
    const auto& linked = s.ws->index();
    std::size_t withParent = 0;
    for (const auto& lv : linked.levels) withParent += lv.ancestors[0] != core::SpatialIndex::kNone;
    auto unlinked = linked;
    unlinked.levels.clear();
    unlinked.blendingLeaves = 0;
    core::RenderSettings rs;
    rs.normalUnsharp = 2.0;
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const auto cpuParent = core::CpuRayCaster(*s.reader, linked, s.ws->slotData(), tf, rs).render(view);
    const auto gpuParent = gpu.render(*s.reader, linked, s.ws->slotBricks(), tf, rs, view);
    const auto cpuOwn = core::CpuRayCaster(*s.reader, unlinked, s.ws->slotData(), tf, rs).render(view);
    const auto gpuOwn = gpu.render(*s.reader, unlinked, s.ws->slotBricks(), tf, rs, view);
    const double parentDb = test::psnr(cpuParent, gpuParent), ownDb = test::psnr(cpuOwn, gpuOwn),
                 apart = test::psnr(cpuParent, cpuOwn);
    std::printf("unsharp masking 2 on %zu leaves with their parent resident: GPU vs CPU %.1f dB with the parent's "
                "gradient, %.1f dB with the leaf's own at twice its spacing; the two %.1f dB apart\n",
                withParent, parentDb, ownDb, apart);
    EXPECT_GT(withParent, 20u);
    EXPECT_GT(parentDb, 80.0);
    EXPECT_GT(ownDb, 80.0);
    EXPECT_LT(apart, 50.0) << "the parent's gradient left the image as the leaf's own drew it";
}
