// Light-field rendering on llvmpipe: the GPU's Screen (MCOP) rays equal the CPU reference; the
// display simulator seen from the virtual viewer equals a direct perspective render from there;
// for shifted observers a marker in front of the screen moves by the geometric amount.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/camera/DisplayModel.h"
#include "core/base/Error.h"
#include "core/image/ImageWriter.h"
#include "core/image/LightFieldSimulator.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include "render/EglOffscreenContext.h"
#include "render/LightFieldRenderer.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/OctreeScene.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
using test::psnr;

// A small projector display: 48 projectors of 96x72 over a 300x225 mm screen.
core::DisplayModel smallDisplay() {
    return core::DisplayModel::parse(R"({"kind":"projector-array","projectors":48,"projectorResolution":[96,72],
        "screenSizeMm":[300,225],"pixelSizeMm":3.1,"beamAngleDegrees":1.0,"fieldOfViewDegrees":48,
        "projectorDistanceMm":600,"observerHeightMm":0,"observerDistanceMm":800})", "small display");
}

using Scene = test::OctreeScene;

// Centroid column of the bright pixels of a MIP image (the marker), -1 when none.
double markerColumn(const core::RenderImage& img) {
    double sum = 0, weight = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float v = img.rgba[std::size_t(y) * std::size_t(img.width) + std::size_t(x)].r;
            if (v > 0.3f) sum += (x + 0.5) * v, weight += v;
        }
    return weight > 0 ? sum / weight : -1;
}
}  // namespace

TEST(LightField, GpuScreenRaysMatchTheCpuReference) {
    core::PhantomVoxelSource phantom({64, 64, 48}, 3, {300, 300, 300}, 5.0);
    Scene s(phantom);
    const auto display = smallDisplay();
    const auto views = display.views(s.centre(), {1, 0, 0}, {0, 0, 1}, 1.0);
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", s.reader->geometry().valueMin,
                                                   s.reader->geometry().valueMax, 1, 0, 4.0);
    const std::vector<core::View> some = {views[3], views[24], views[44]};
    const auto cpu = render::LightFieldRenderer::render(*s.reader, *s.ws, *s.loader, tf, {}, some,
                                                        display.accuracyFunction(), nullptr, true);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const auto gpuImages = render::LightFieldRenderer::render(*s.reader, *s.ws, *s.loader, tf, {}, some,
                                                              display.accuracyFunction(), &gpu, true);
    for (std::size_t i = 0; i < some.size(); ++i) {
        const double db = psnr(gpuImages[i], cpu[i]);
        std::printf("projector view %zu: GPU vs CPU %.1f dB\n", i, db);
        EXPECT_GT(db, 80.0) << "measured 89.5 dB and up";
    }
}

TEST(LightField, SimulatorAtTheVirtualViewerMatchesADirectPerspectiveRender) {
    core::PhantomVoxelSource phantom({64, 64, 48}, 3, {300, 300, 300}, 5.0);
    Scene s(phantom);
    const auto display = smallDisplay();
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", s.reader->geometry().valueMin,
                                                   s.reader->geometry().valueMax, 1, 0, 4.0);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const auto views = display.views(s.centre(), {1, 0, 0}, {0, 0, 1}, 1.0);
    const auto projectors = render::LightFieldRenderer::render(*s.reader, *s.ws, *s.loader, tf, {}, views,
                                                               display.accuracyFunction(), &gpu, true);
    const glm::dvec3 V(0, display.observerHeightMm, display.observerDistanceMm);
    const auto seen = core::LightFieldSimulator::observe(display, projectors, V);
    // Direct: one perspective view from V through the screen (eta = 0), same cut.
    auto direct = views.front();
    direct.screen.eta = 0.0;
    const auto want = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, {}, direct);
    const double db = psnr(seen, want);
    std::printf("simulated view at V vs direct perspective render: PSNR %.1f dB\n", db);
    if (db < 35.0) {
        core::ImageWriter::write(seen, HVX_BINARY_DIR "/test-artifacts/lightfield-simulated.png");
        core::ImageWriter::write(want, HVX_BINARY_DIR "/test-artifacts/lightfield-direct.png");
    }
    EXPECT_GT(db, 35.0) << "each column comes from the nearest of 48 projectors, within 1 degree (measured 38.6 dB)";
}

TEST(LightField, AMarkerInFrontOfTheScreenShiftsByTheGeometricAmountForShiftedObservers) {
    // A bright 7 mm cube 60 mm in front of the screen (towards the viewer: -y in LPS for this frame).
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.spacing = {1, 1, 1};
    g.origin = {-40, -80, -40};  // y from -80 (anterior) to +40 mm
    test::DenseVolume v;
    v.dims = {81, 121, 81};
    v.values.assign(81 * 121 * 81, 0.0);
    const glm::ivec3 marker(40, 20, 40);  // x = 0, y = -60 mm (anterior), z = 0
    for (int z = -3; z <= 3; ++z)
        for (int y = -3; y <= 3; ++y)
            for (int x = -3; x <= 3; ++x)
                v.values[std::size_t(((marker.z + z) * 121 + marker.y + y) * 81 + marker.x + x)] = 255;
    test::MemoryVoxelSource source(g, v);
    Scene s(source);
    const auto display = smallDisplay();
    const auto tf = core::TransferFunction::preset("mip-ramp", 0, 255, 1, 0, 1.0);
    core::RenderSettings mip;
    mip.mode = core::RenderSettings::Mode::Mip;
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    // Screen at the volume centre (patient origin), right = patient left, up = superior: the
    // display's z axis points anterior, so the marker is at display z = +60.
    const auto views = display.views({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 1.0);
    const auto projectors = render::LightFieldRenderer::render(*s.reader, *s.ws, *s.loader, tf, mip, views,
                                                               display.accuracyFunction(), &gpu, true);
    const double Qz = 60.0, Pz = display.observerDistanceMm;
    const double pixelMm = display.screenWidthMm / display.projectorWidth;
    double reference = 0;
    for (double px : {-120.0, 0.0, 120.0}) {
        const auto seen = core::LightFieldSimulator::observe(display, projectors, {px, 0, Pz});
        const double column = markerColumn(seen);
        ASSERT_GE(column, 0) << "observer at x = " << px << " sees the marker";
        // Where the line from the observer P to the marker Q meets the screen (z = 0).
        const double screenX = px + (0.0 - px) * (0.0 - Pz) / (Qz - Pz);
        const double expected = screenX / pixelMm + display.projectorWidth / 2.0;
        std::printf("observer x %+.0f mm: marker at column %.2f, geometry says %.2f\n", px, column, expected);
        EXPECT_NEAR(column, expected, 0.5) << "measured within 0.25 px";
        if (px == 0.0) reference = column;
    }
    EXPECT_GT(reference, 0);
}

TEST(LightField, ABatchOfViewsInOneDispatchEqualsViewsDrawnOneByOne) {
    core::PhantomVoxelSource phantom({64, 64, 48}, 3, {300, 300, 300}, 5.0);
    Scene s(phantom);
    const auto display = smallDisplay();
    const auto views = display.views(s.centre(), {1, 0, 0}, {0, 0, 1}, 1.0);
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", s.reader->geometry().valueMin,
                                                   s.reader->geometry().valueMax, 1, 0, 4.0);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const std::vector<core::View> some(views.begin(), views.begin() + 7);
    render::LightFieldRenderer::render(*s.reader, *s.ws, *s.loader, tf, {}, some, display.accuracyFunction(), nullptr, true);
    const auto batch = gpu.renderViews(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, {}, some);
    ASSERT_EQ(batch.size(), some.size());
    for (std::size_t i = 0; i < some.size(); ++i) {
        const auto single = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, {}, some[i]);
        for (std::size_t k = 0; k < single.rgba.size(); ++k) ASSERT_EQ(batch[i].rgba[k], single.rgba[k]) << "view " << i;
    }
    auto other = some;
    other.back().width = 10;
    EXPECT_THROW(gpu.renderViews(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, {}, other), core::Error);
}
