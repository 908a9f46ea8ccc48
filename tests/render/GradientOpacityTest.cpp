// Gradient opacity (MedVis §3.2.1): opacity scaled by a curve over the gradient magnitude, on the
// GPU and in the CPU reference alike. A flat curve is no curve (the image is bitwise today's);
// a curve that silences small gradients fades homogeneous tissue and keeps its boundaries.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/reference/CpuRayCaster.h"
#include "core/volume/PhantomVoxelSource.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/PhantomScene.h"

using namespace hvx;

namespace {
double meanAlpha(const core::RenderImage& img) {
    double sum = 0;
    for (const auto& p : img.rgba) sum += p.a;
    return sum / double(img.rgba.size());
}
}  // namespace

TEST(GradientOpacity, GpuEqualsCpuAndAFlatCurveChangesNothing) {
    test::PhantomScene s;
    const auto& g = s.reader->geometry();
    const auto& plain = s.tf;
    auto flat = plain;
    flat.setGradientOpacity({{0, 1}, {500, 1}});
    EXPECT_FALSE(flat.hasGradientOpacity());
    auto edges = plain;  // nothing below 20 HU per mm, everything above 80 (stored units: slope 1)
    edges.setGradientOpacity({{20.0 / g.rescaleSlope, 0.0}, {80.0 / g.rescaleSlope, 1.0}});
    ASSERT_TRUE(edges.hasGradientOpacity());
    EXPECT_DOUBLE_EQ(edges.gradientScale(0.0), 0.0);
    EXPECT_NEAR(edges.gradientScale(50.0 / g.rescaleSlope), 0.5, 0.01);
    EXPECT_DOUBLE_EQ(edges.gradientScale(500.0), 1.0);

    const auto& view = s.view;
    s.converge();
    const core::RenderSettings rs;
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const auto cpuPlain = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), plain, rs).render(view);
    const auto cpuFlat = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), flat, rs).render(view);
    const auto gpuPlain = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), plain, rs, view);
    const auto gpuFlat = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), flat, rs, view);
    EXPECT_EQ(test::psnr(cpuPlain, cpuFlat), 99.0) << "a flat curve changed the CPU image";
    EXPECT_EQ(test::psnr(gpuPlain, gpuFlat), 99.0) << "a flat curve changed the GPU image";

    const auto cpu = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), edges, rs).render(view);
    const auto gl = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), edges, rs, view);
    const double db = test::psnr(cpu, gl), change = test::psnr(cpu, cpuPlain);
    std::printf("gradient opacity: GPU vs CPU %.1f dB; against the plain image %.1f dB; mean opacity %.3f -> %.3f\n", db,
                change, meanAlpha(cpuPlain), meanAlpha(cpu));
    EXPECT_GT(db, 80.0);
    EXPECT_LT(change, 35.0) << "the curve changed little: the test would not see it ignored";
    EXPECT_LT(meanAlpha(cpu), meanAlpha(cpuPlain)) << "homogeneous tissue did not fade";
}
