// Refraction (thesis §3.2.2, Figs 3.4–3.5): with a refraction index ν(s), DVR rays bend at each
// step by Snell's law. A transparent slab of constant ν offsets a marker seen through it by what
// Snell's law predicts, worked by hand below; GPU and CPU reference draw the same image; ν ≡ 1
// is no refraction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/base/Error.h"
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
/// 96³ voxels of 1 mm (index = patient mm): air (0); a slab of value −100 at k 30–49 (its faces,
/// half-way between voxel centres, at k = 29.5 and 49.5: 20 mm thick); behind it a marker rod of
/// value 200 along j, 4×4 voxels at i 46–49, k 70–73, j 20–75. The slab's values lie below air's
/// and the marker's above, so no value of the marker's faces refracts.
test::MemoryVoxelSource slabAndMarker() {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Float32;
    g.dims = {96, 96, 96};
    g.valueMin = -150;
    g.valueMax = 300;
    return test::MemoryVoxelSource(g, test::generatedVolume(g.dims, [](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
                                       const bool slab = k >= 30 && k < 50;
                                       const bool marker = i >= 46 && i < 50 && k >= 70 && k < 74 && j >= 20 && j < 76;
                                       return marker ? 200.0 : slab ? -100.0 : 0.0;
                                   }));
}

/// Transparent air and slab, an opaque white marker; the slab's values refract by `nu`.
core::TransferFunction slabFunction(double nu) {
    core::TransferFunction tf({{0, glm::dvec4(0.0)}, {150, glm::dvec4(1, 1, 1, 0)}, {200, glm::dvec4(1, 1, 1, 1)}}, -150, 300);
    tf.setRefraction({{-100, nu}, {0, 1.0}});
    return tf;
}

/// The opacity-weighted mean column of the image's middle row between columns 100 and 140,
/// where the marker is seen straight and through the slab. (Rays that enter the volume through
/// its side face inside the slab start in the slab's medium, since a cut face is not a boundary,
/// and leave its far face steeply: they may meet the marker far off.)
double markerColumn(const core::RenderImage& img) {
    double sum = 0, weight = 0;
    const int y = img.height / 2;
    for (int x = 100; x < 140; ++x) {
        const float a = img.rgba[std::size_t(y) * std::size_t(img.width) + std::size_t(x)].a;
        sum += a * (x + 0.5);
        weight += a;
    }
    return weight > 0 ? sum / weight : -1.0;
}
}  // namespace

TEST(Refraction, ASlabOffsetsTheMarkerBehindItAsSnellsLawPredicts) {
    auto source = slabAndMarker();
    test::OctreeScene s(source);
    // Orthographic, looking 40° from the slab's normal (+k) in the i–k plane; the image's x axis
    // is r = (−cos 40°, 0, sin 40°), its y axis +j. 192 pixels over 96 mm: 0.5 mm a pixel.
    const double theta = glm::radians(40.0);
    const glm::dvec3 f(std::sin(theta), 0.0, std::cos(theta)), centre(47.5, 47.5, 47.5);
    core::View view;
    view.model = core::View::Model::Orthographic;
    view.target = centre;
    view.eye = centre - 200.0 * f;
    view.up = {0.0, 1.0, 0.0};
    view.orthoHeight = 96.0;
    view.width = view.height = 192;
    const auto plainTf = slabFunction(1.0), refractTf = slabFunction(1.5);
    ASSERT_FALSE(plainTf.hasRefraction());
    ASSERT_TRUE(refractTf.hasRefraction());
    s.ws->converge({view}, refractTf);
    // By hand: inside the slab sin θ1 = sin 40° / 1.5 = 0.42853, θ1 = 25.37°; the ray leaves it
    // parallel to how it came in, moved along the slab by T (tan θ0 − tan θ1) = 20 × (0.83910 −
    // 0.47428) = 7.2964 mm less, which is 7.2964 × cos 40° = 5.589 mm across the view, towards +r:
    // the marker is seen 5.589 mm (11.2 pixels) towards −r.
    const double expected = -20.0 * (std::tan(theta) - std::tan(std::asin(std::sin(theta) / 1.5))) * std::cos(theta) / 0.5;
    EXPECT_NEAR(expected, -11.18, 0.01);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    core::RenderSettings rs;
    rs.shading = false;
    const auto gpuPlain = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), plainTf, rs, view);
    const auto gpuBent = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), refractTf, rs, view);
    const auto cpuPlain = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), plainTf, rs).render(view);
    const auto cpuBent = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), refractTf, rs).render(view);
    // Without refraction the marker sits where it projects: its centre (48, ·, 72) is
    // (48 − 47.5)·(−cos 40°) + (72 − 47.5)·sin 40° = 15.37 mm right of the centre, column 126.7.
    const double straight = 96.0 + ((48.0 - 47.5) * -std::cos(theta) + (72.0 - 47.5) * std::sin(theta)) / 0.5;
    EXPECT_NEAR(markerColumn(gpuPlain), straight, 0.5);
    EXPECT_NEAR(markerColumn(cpuPlain), straight, 0.5);
    const double gpuShift = markerColumn(gpuBent) - markerColumn(gpuPlain);
    const double cpuShift = markerColumn(cpuBent) - markerColumn(cpuPlain);
    std::printf("marker at column %.2f straight; through the slab (ν 1.5) moved %.2f px on the GPU, %.2f px on the CPU; "
                "Snell's law: %.2f px\n",
                markerColumn(gpuPlain), gpuShift, cpuShift, expected);
    // Within a pixel: the slab's faces are trilinear ramps one voxel wide, crossed in steps of a voxel.
    EXPECT_NEAR(gpuShift, expected, 1.0);
    EXPECT_NEAR(cpuShift, expected, 1.0);
    const double slabDb = test::psnr(cpuBent, gpuBent);
    std::printf("slab and marker: GPU vs CPU %.1f dB\n", slabDb);
    EXPECT_GT(slabDb, 80.0);
    // The marker's image keeps its width (the rays leave the slab parallel).
    auto width = [](const core::RenderImage& img) {
        double w = 0;
        for (int x = 100; x < 140; ++x) w += img.rgba[std::size_t(img.height / 2) * std::size_t(img.width) + std::size_t(x)].a;
        return w;
    };
    EXPECT_NEAR(width(gpuBent), width(gpuPlain), 1.0);
}

TEST(Refraction, GpuEqualsTheCpuReferenceAndAnIndexOfOneIsNoRefraction) {
    test::PhantomScene s;
    const auto& g = s.reader->geometry();
    const auto& plain = s.tf;
    const auto& view = s.view;
    s.converge();
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    core::RenderSettings rs;
    const auto gpuPlain = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), plain, rs, view);
    const auto cpuPlain = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), plain, rs).render(view);
    // ν ≡ 1: no curve, the plain march, bitwise.
    auto ones = plain;
    ones.setRefraction({{g.valueMin, 1.0}, {g.valueMax, 1.0}});
    EXPECT_FALSE(ones.hasRefraction());
    EXPECT_EQ(test::psnr(gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), ones, rs, view), gpuPlain), 99.0);
    // An index ≠ 1 only at values the volume does not hold: the refract stepper runs and bends
    // nothing; its samples are the plain march's but for where a ray leaves empty space.
    auto absent = plain;
    absent.setRefraction({{g.valueMax - 2.0, 1.0}, {g.valueMax - 1.0, 1.5}});
    ASSERT_TRUE(absent.hasRefraction());
    const auto gpuAbsent = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), absent, rs, view);
    const double straightDb = test::psnr(gpuAbsent, gpuPlain);
    // The body refracts as water (ν 1.33) and air does not: the index steps between −600 and
    // −400 HU, clear of the values the phantom's noise spreads air, lung and tissue over.
    auto water = plain;
    auto stored = [&](double hu) { return (hu - g.rescaleIntercept) / g.rescaleSlope; };
    water.setRefraction({{stored(-600), 1.0}, {stored(-400), 1.33}});
    const auto cpu = core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), water, rs).render(view);
    const auto gl = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), water, rs, view);
    const double db = test::psnr(cpu, gl), change = test::psnr(cpu, cpuPlain);
    // How far the CPU reference departs from itself when every ray starts 0.1 µm to the side.
    auto nudged = view;
    nudged.eye += glm::dvec3(1e-4, 0.0, 0.0);
    nudged.target += glm::dvec3(1e-4, 0.0, 0.0);
    const double selfDb = test::psnr(cpu, core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), water, rs).render(nudged));
    const double plainSelfDb =
        test::psnr(cpuPlain, core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), plain, rs).render(nudged));
    std::size_t apart = 0;  // pixels more than 0.02 apart
    for (std::size_t i = 0; i < cpu.rgba.size(); ++i) apart += glm::length(cpu.rgba[i] - gl.rgba[i]) > 0.02f;
    std::printf("refract stepper bending nothing vs the plain march %.1f dB; body at ν 1.33: GPU vs CPU %.1f dB "
                "(%zu of %zu pixels more than 0.02 apart), against no refraction %.1f dB; the CPU reference against "
                "itself with the camera 0.1 µm aside: %.1f dB refracted, %.1f dB straight\n",
                straightDb, db, apart, cpu.rgba.size(), change, selfDb, plainSelfDb);
    EXPECT_GT(straightDb, 45.0);
    // A bent ray carries each rounding of its samples and normals on to every later step, and
    // the phantom's noisy tissue (large value changes per voxel) turns a path drifted by a tiny
    // distance into a visible difference: the CPU reference itself, with every ray started
    // 0.1 µm aside, departs from its own image as far as the GPU does (48.4 vs 49.0 dB
    // measured), while the straight march moves by nothing visible (> 100 dB). So on noisy data
    // no two implementations agree to 80 dB unless bit for bit; the test holds the GPU to the
    // reference's own sensitivity (3 dB of slack) and to scattered rays (0.5 % measured); the
    // slab above, smooth boundaries in clear air, agrees to > 80 dB.
    EXPECT_LT(selfDb, 60.0) << "the data no longer amplifies a ray's drift: hold the GPU to 80 dB here";
    EXPECT_GT(plainSelfDb, 90.0);
    EXPECT_GT(db, selfDb - 3.0) << "the GPU departs from the reference more than the reference from itself";
    EXPECT_LT(apart, cpu.rgba.size() / 100) << "more than 1 % of the pixels differ";
    EXPECT_LT(change, 40.0) << "refraction changes the image";
    // Refraction is drawn without the tools (a sentence, not a plausible image).
    auto withTools = rs;
    withTools.tools.clip.enabled = true;
    EXPECT_THROW(gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), water, withTools, view), core::Error);
    EXPECT_THROW(core::CpuRayCaster(*s.reader, s.ws->index(), s.ws->slotData(), water, withTools), core::Error);
}
