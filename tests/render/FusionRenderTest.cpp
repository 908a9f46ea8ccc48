// Two volumes in one ray march (core::FusedRayCaster, the GPU's HVX_FUSION variant): a second
// volume on another grid (rotated, anisotropic, its own origin) laid over the first. Markers
// placed at the same LPS points in both land on the same pixels, where the camera projects those
// points (an independent check through View::viewProjection); the same markers written into a
// volume whose geometry is misstated land elsewhere (the check can fail). GPU equals the CPU
// reference; a fused volume that shows nothing leaves the base volume's image as it was; a
// label map fused over an image shows no colour that is not a label's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/appearance/LabelTable.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/CpuRayCaster.h"
#include "core/reference/FusedRayCaster.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const glm::dvec3 kMarkers[2] = {{-10.0, -6.0, -12.0}, {9.0, 8.0, 10.0}};  // LPS mm

/// A volume of `dims` voxels centred on the LPS origin, with value 200 within `radius` mm of
/// each marker (where `truth` puts the voxel centres) and 0 elsewhere, written with geometry g.
test::DenseVolume markers(const core::VolumeGeometry& truth, double radius, int value = 200) {
    test::DenseVolume v;
    v.dims = truth.dims;
    v.values.resize(std::size_t(v.dims[0]) * v.dims[1] * v.dims[2]);
    std::size_t n = 0;
    for (std::uint32_t k = 0; k < v.dims[2]; ++k)
        for (std::uint32_t j = 0; j < v.dims[1]; ++j)
            for (std::uint32_t i = 0; i < v.dims[0]; ++i) {
                const glm::dvec3 p = truth.origin + truth.direction * (glm::dvec3(i, j, k) * truth.spacing);
                double value_ = 0;
                for (const auto& m : kMarkers)
                    if (glm::length(p - m) <= radius) value_ = value;
                v.values[n++] = value_;
            }
    return v;
}

core::VolumeGeometry grid(std::array<std::uint32_t, 3> dims, glm::dvec3 spacing, glm::dmat3 direction) {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.dims = dims;
    g.spacing = spacing;
    g.direction = direction;
    g.origin = -direction * ((glm::dvec3(dims[0], dims[1], dims[2]) - 1.0) * spacing * 0.5);
    g.valueMin = 0;
    g.valueMax = 255;
    g.frameOfReferenceUid = "1.2.3.4";
    return g;
}

struct Scene {
    std::unique_ptr<core::OctreeReader> reader;
    std::unique_ptr<core::BrickCache> cache;
    std::unique_ptr<core::BrickLoader> loader;
    std::unique_ptr<core::WorkingSet> ws;
};

Scene build(const std::string& path, const core::VolumeGeometry& g, test::DenseVolume v, bool labels,
            const core::TransferFunction& tf, const core::View& view) {
    core::JobContext job;
    test::MemoryVoxelSource source(g, std::move(v));
    core::BuildOptions options;
    options.brickSize = 16;  // several bricks and levels for these small volumes
    options.labels = labels;
    core::OctreeBuilder(options).build(source, path, job);
    Scene s;
    s.reader = core::OctreeReader::open(path);
    s.cache = std::make_unique<core::BrickCache>(1u << 28);
    s.loader = std::make_unique<core::BrickLoader>(*s.reader, *s.cache);
    s.ws = std::make_unique<core::WorkingSet>(*s.reader, *s.cache, *s.loader, core::WorkingSetOptions{});
    s.ws->converge({view}, tf);
    return s;
}

core::TransferFunction solid(glm::dvec3 colour, double opacity = 1.0) {
    return core::TransferFunction({{0, glm::dvec4(0.0)}, {99, glm::dvec4(0.0)}, {100, glm::dvec4(colour, opacity)},
                                   {255, glm::dvec4(colour, opacity)}},
                                  0, 255, 1.0);
}

/// Where the camera puts an LPS point (pixel centres at +0.5, y down).
glm::dvec2 project(const core::View& view, const glm::dvec3& p) {
    const glm::dvec4 c = view.viewProjection() * glm::dvec4(p, 1.0);
    return {(c.x / c.w * 0.5 + 0.5) * view.width, (0.5 - c.y / c.w * 0.5) * view.height};
}

/// The centroid of one colour channel's weight within `radius` pixels of `around`.
glm::dvec2 centroid(const core::RenderImage& img, int channel, glm::dvec2 around, int radius = 12) {
    glm::dvec2 sum(0.0);
    double weight = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const glm::dvec2 c(x + 0.5, y + 0.5);
            if (std::abs(c.x - around.x) > radius || std::abs(c.y - around.y) > radius) continue;
            const double w = img.rgba[std::size_t(y) * img.width + x][channel];
            sum += w * c;
            weight += w;
        }
    return weight > 0 ? sum / weight : glm::dvec2(1e9);
}

glm::dmat3 rotated() {  // 30° about z, then 20° about x
    const glm::dmat4 r = glm::rotate(glm::rotate(glm::dmat4(1.0), glm::radians(20.0), glm::dvec3(1, 0, 0)),
                                     glm::radians(30.0), glm::dvec3(0, 0, 1));
    return glm::dmat3(r);
}
}  // namespace

TEST(Fusion, MarkersOnTwoGridsCoincideAndGpuEqualsCpu) {
    test::TempDir dir;
    const auto view = core::View::orbit(glm::dvec3(0.0), 150.0, 30.0, 20.0, 128, 128);
    const auto gA = grid({48, 48, 40}, {1.0, 1.0, 1.5}, glm::dmat3(1.0));
    const auto gB = grid({40, 36, 44}, {1.3, 0.9, 1.1}, rotated());
    auto gWrong = gB;  // the same voxels, their rotation forgotten
    gWrong.direction = glm::dmat3(1.0);
    gWrong.origin = grid(gB.dims, gB.spacing, glm::dmat3(1.0)).origin;
    // Faint markers: each colour's weight comes from its whole ball, not from whichever surface
    // happens to lie in front of the other's.
    const auto red = solid({1, 0, 0}, 0.1), green = solid({0, 1, 0}, 0.1);
    auto a = build(dir.file("a.hvo"), gA, markers(gA, 3.0), false, red, view);
    auto b = build(dir.file("b.hvo"), gB, markers(gB, 3.0), false, green, view);
    auto wrong = build(dir.file("wrong.hvo"), gWrong, markers(gB, 3.0), false, green, view);

    core::RenderSettings rs;
    rs.shading = false;  // colours as the transfer functions give them
    const core::CpuRayCaster baseCpu(*a.reader, a.ws->index(), a.ws->slotData(), red, rs);
    const auto cpu = core::FusedRayCaster(baseCpu, core::CpuRayCaster(*b.reader, b.ws->index(), b.ws->slotData(), green, rs))
                         .render(view);
    const auto misplaced =
        core::FusedRayCaster(baseCpu, core::CpuRayCaster(*wrong.reader, wrong.ws->index(), wrong.ws->slotData(), green, rs))
            .render(view);
    double worstMisplaced = 0;
    for (const auto& m : kMarkers) {
        const glm::dvec2 at = project(view, m);
        const glm::dvec2 r = centroid(cpu, 0, at), g = centroid(cpu, 1, at), w = centroid(misplaced, 1, at);
        std::printf("marker (%g, %g, %g) projects to (%.2f, %.2f): base at (%.2f, %.2f), fused at (%.2f, %.2f); "
                    "misstated geometry at (%.2f, %.2f)\n",
                    m.x, m.y, m.z, at.x, at.y, r.x, r.y, g.x, g.y, w.x, w.y);
        EXPECT_LT(glm::length(r - at), 0.75) << "the base volume's marker is off its LPS point";
        EXPECT_LT(glm::length(g - at), 0.75) << "the fused volume's marker is off its LPS point";
        EXPECT_LT(glm::length(g - r), 0.5) << "the two markers do not coincide";
        worstMisplaced = std::max(worstMisplaced, glm::length(w - at));
    }
    EXPECT_GT(worstMisplaced, 3.0) << "a misstated rotation went unseen: the check cannot fail";

    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const render::GpuRayCaster::Overlay overlay{*b.reader, b.ws->index(), b.ws->slotBricks(), green};
    const auto gl = gpu.render(*a.reader, a.ws->index(), a.ws->slotBricks(), red, rs, view, &overlay);
    const double db = test::psnr(cpu, gl);
    core::RenderSettings lit;  // shaded, each volume with its own gradient
    const auto cpuLit = core::FusedRayCaster(core::CpuRayCaster(*a.reader, a.ws->index(), a.ws->slotData(), red, lit),
                                             core::CpuRayCaster(*b.reader, b.ws->index(), b.ws->slotData(), green, lit))
                            .render(view);
    const double dbLit = test::psnr(cpuLit, gpu.render(*a.reader, a.ws->index(), a.ws->slotBricks(), red, lit, view, &overlay));
    std::printf("fused frame, GPU vs CPU: %.1f dB unshaded, %.1f dB shaded\n", db, dbLit);
    EXPECT_GT(db, 80.0);
    EXPECT_GT(dbLit, 60.0);
}

TEST(Fusion, AnOverlayThatShowsNothingLeavesTheBaseImage) {
    test::TempDir dir;
    const auto view = core::View::orbit(glm::dvec3(0.0), 150.0, -40.0, 10.0, 96, 96);
    const auto gA = grid({48, 48, 40}, {1.0, 1.0, 1.5}, glm::dmat3(1.0));
    const auto gB = grid({40, 36, 44}, {1.3, 0.9, 1.1}, rotated());
    const auto red = solid({1, 0.3, 0.2}, 0.6);
    const core::TransferFunction nothing({{0, glm::dvec4(0.0)}, {255, glm::dvec4(0.0)}}, 0, 255, 1.0);
    auto a = build(dir.file("a.hvo"), gA, markers(gA, 6.0), false, red, view);
    auto b = build(dir.file("b.hvo"), gB, markers(gB, 6.0), false, nothing, view);
    const core::RenderSettings rs;
    const core::CpuRayCaster base(*a.reader, a.ws->index(), a.ws->slotData(), red, rs);
    const auto plain = base.render(view);
    const auto fused = core::FusedRayCaster(base, core::CpuRayCaster(*b.reader, b.ws->index(), b.ws->slotData(), nothing, rs))
                           .render(view);
    const double db = test::psnr(plain, fused);
    std::printf("base volume alone vs fused with a transparent overlay: %.1f dB\n", db);
    // Not bitwise: after empty space the fused march resumes where the leaf starts, the plain
    // one on its own sampling grid.
    EXPECT_GT(db, 45.0);
}

TEST(Fusion, ALabelMapOverAnImageShowsOnlyItsLabelsColours) {
    test::TempDir dir;
    const auto view = core::View::orbit(glm::dvec3(0.0), 150.0, 75.0, -15.0, 96, 96);
    const auto gA = grid({48, 48, 40}, {1.0, 1.0, 1.5}, glm::dmat3(1.0));
    auto gL = grid({40, 36, 44}, {1.3, 0.9, 1.1}, rotated());
    gL.isLabel = true;
    // Label 1 around the first marker, label 3 around the second, 2 (green) nowhere: a blend of
    // 1 and 3 would show it.
    auto labels = markers(gL, 7.0, 1);
    for (std::size_t i = 0, n = 0; i < labels.values.size(); ++i, ++n) {
        const std::uint32_t x = std::uint32_t(n % gL.dims[0]);
        if (labels.values[i] > 0 && x > gL.dims[0] / 2) labels.values[i] = 3;
    }
    core::LabelTable table;
    table.set(1, {"one", {255, 0, 0, 255}});
    table.set(2, {"two", {0, 255, 0, 255}});
    table.set(3, {"three", {0, 0, 255, 255}});
    const auto tfL = core::TransferFunction::forLabels(table, 1.0, 1.0);
    const core::TransferFunction nothing({{0, glm::dvec4(0.0)}, {255, glm::dvec4(0.0)}}, 0, 255, 1.0);
    auto a = build(dir.file("a.hvo"), gA, markers(gA, 6.0), false, nothing, view);
    auto l = build(dir.file("l.hvo"), gL, std::move(labels), true, tfL, view);
    ASSERT_TRUE(l.reader->geometry().isLabel);
    core::RenderSettings rs;
    rs.shading = false;
    const auto cpu = core::FusedRayCaster(core::CpuRayCaster(*a.reader, a.ws->index(), a.ws->slotData(), nothing, rs),
                                          core::CpuRayCaster(*l.reader, l.ws->index(), l.ws->slotData(), tfL, rs))
                         .render(view);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const render::GpuRayCaster::Overlay overlay{*l.reader, l.ws->index(), l.ws->slotBricks(), tfL};
    const auto gl = gpu.render(*a.reader, a.ws->index(), a.ws->slotBricks(), nothing, rs, view, &overlay);
    for (const auto* img : {&cpu, &gl}) {
        int covered = 0, foreign = 0;
        for (const auto& p : img->rgba) {
            if (p.a < 0.05f) continue;
            ++covered;
            const glm::vec3 c = glm::vec3(p) / p.a;
            const bool known = (c.r > 0.98f && c.g < 0.02f && c.b < 0.02f) || (c.b > 0.98f && c.r < 0.02f && c.g < 0.02f);
            foreign += known ? 0 : 1;
        }
        std::printf("%s: %d pixels covered, %d of a colour no label has\n", img == &cpu ? "CPU" : "GPU", covered, foreign);
        EXPECT_GT(covered, 300);
        EXPECT_EQ(foreign, 0);
    }
    EXPECT_GT(test::psnr(cpu, gl), 60.0);
}

// Gradient opacity in the fused march (MedVis §3.2.1): each volume's opacity is scaled by its own
// curve over its own gradient, the base's and the overlay's alike, on the GPU as in the CPU
// reference; a flat curve is no curve (the fused image bitwise today's).
TEST(Fusion, EachVolumeScalesItsOpacityByItsOwnGradientCurve) {
    test::TempDir dir;
    const auto view = core::View::orbit(glm::dvec3(0.0), 150.0, 30.0, 20.0, 128, 128);
    const auto gA = grid({48, 48, 40}, {1.0, 1.0, 1.5}, glm::dmat3(1.0));
    const auto gB = grid({40, 36, 44}, {1.3, 0.9, 1.1}, rotated());
    // A faint base, so that the overlay's balls inside its own show through.
    const auto red = solid({1, 0.2, 0.1}, 0.1), green = solid({0.1, 1, 0.2}, 0.5);
    auto a = build(dir.file("a.hvo"), gA, markers(gA, 8.0), false, red, view);
    auto b = build(dir.file("b.hvo"), gB, markers(gB, 6.0), false, green, view);
    // The balls are uniform inside (|∇f| 0) and step from 0 to 200 at their surfaces.
    auto redEdges = red, greenEdges = green, redFlat = red;
    redEdges.setGradientOpacity({{0.0, 0.0}, {20.0, 1.0}});
    greenEdges.setGradientOpacity({{10.0, 0.0}, {40.0, 1.0}});
    redFlat.setGradientOpacity({{0.0, 1.0}, {50.0, 1.0}});
    ASSERT_FALSE(redFlat.hasGradientOpacity());

    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    for (const bool shaded : {false, true}) {
        core::RenderSettings rs;
        rs.shading = shaded;
        auto cpuFused = [&](const core::TransferFunction& ta, const core::TransferFunction& tb) {
            return core::FusedRayCaster(core::CpuRayCaster(*a.reader, a.ws->index(), a.ws->slotData(), ta, rs),
                                        core::CpuRayCaster(*b.reader, b.ws->index(), b.ws->slotData(), tb, rs))
                .render(view);
        };
        auto gpuFused = [&](const core::TransferFunction& ta, const core::TransferFunction& tb) {
            const render::GpuRayCaster::Overlay overlay{*b.reader, b.ws->index(), b.ws->slotBricks(), tb};
            return gpu.render(*a.reader, a.ws->index(), a.ws->slotBricks(), ta, rs, view, &overlay);
        };
        const auto cpuPlain = cpuFused(red, green), gpuPlain = gpuFused(red, green);
        EXPECT_EQ(test::psnr(cpuPlain, cpuFused(redFlat, green)), 99.0) << "a flat curve changed the CPU image";
        EXPECT_EQ(test::psnr(gpuPlain, gpuFused(redFlat, green)), 99.0) << "a flat curve changed the GPU image";
        const std::pair<const core::TransferFunction*, const core::TransferFunction*> cases[] = {
            {&redEdges, &green}, {&red, &greenEdges}, {&redEdges, &greenEdges}};
        const char* names[] = {"base's curve", "overlay's curve", "both curves"};
        for (int i = 0; i < 3; ++i) {
            const auto cpu = cpuFused(*cases[i].first, *cases[i].second);
            const auto gl = gpuFused(*cases[i].first, *cases[i].second);
            const double db = test::psnr(cpu, gl), change = test::psnr(cpu, cpuPlain);
            std::printf("fused, %s, %s: GPU vs CPU %.1f dB; against no curve %.1f dB\n", shaded ? "shaded" : "unshaded",
                        names[i], db, change);
            EXPECT_GT(db, 80.0) << names[i];
            EXPECT_LT(change, 40.0) << names[i] << ": the curve changed little, the test would not see it ignored";
        }
    }
}
