// A label map in the 3D view: each sample is the nearest voxel's label, classified by its own
// table entry, so no pixel shows a colour that is not a label's, on the CPU reference and on
// the GPU alike. The same voxels rendered as an ordinary image (trilinear, pre-integrated) do
// show other colours: the check can fail.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/appearance/LabelTable.h"
#include "core/base/Error.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/CpuRayCaster.h"
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
const std::vector<std::pair<int, glm::vec3>> kColours = {
    {1, {1, 0, 0}}, {2, {0, 1, 0}}, {3, {0, 0, 1}}, {9, {1, 1, 0}}};

// Blocks of labels 1, 3 and 9 side by side in a ball (2 lies between 1 and 3 in value but
// touches neither: a blend of 1 and 3 would show its green), label 0 around it.
test::DenseVolume blocks() {
    test::DenseVolume v;
    v.dims = {40, 36, 32};
    v.values.resize(std::size_t(v.dims[0]) * v.dims[1] * v.dims[2]);
    const int cycle[3] = {1, 3, 9};
    std::size_t n = 0;
    for (std::uint32_t k = 0; k < v.dims[2]; ++k)
        for (std::uint32_t j = 0; j < v.dims[1]; ++j)
            for (std::uint32_t i = 0; i < v.dims[0]; ++i) {
                const double x = i - 19.5, y = j - 17.5, z = k - 15.5;
                const bool inside = x * x + y * y + z * z < 15.0 * 15.0;
                v.values[n++] = inside ? (i / 5 + j / 6 + k / 4 == 4 ? 2 : cycle[(i / 5 + j / 6 + k / 4) % 3]) : 0;
            }
    return v;
}

// Pixels whose colour (un-premultiplied) is no label's, among those with any opacity.
int foreignPixels(const core::RenderImage& img, int& covered) {
    int foreign = 0;
    covered = 0;
    for (const auto& p : img.rgba) {
        if (p.a < 0.05f) continue;
        ++covered;
        const glm::vec3 c = glm::vec3(p) / p.a;
        bool known = false;
        for (const auto& [label, colour] : kColours) {
            const glm::vec3 d = glm::abs(c - colour);
            known = known || std::max({d.x, d.y, d.z}) <= 0.02f;
        }
        foreign += known ? 0 : 1;
    }
    return foreign;
}

struct Scene {
    std::unique_ptr<core::OctreeReader> reader;
    std::unique_ptr<core::BrickCache> cache;
    std::unique_ptr<core::BrickLoader> loader;
    std::unique_ptr<core::WorkingSet> ws;
};

Scene open(const std::string& path, const core::TransferFunction& tf, const std::vector<core::View>& views) {
    Scene s;
    s.reader = core::OctreeReader::open(path);
    s.cache = std::make_unique<core::BrickCache>(1u << 28);
    s.loader = std::make_unique<core::BrickLoader>(*s.reader, *s.cache);
    s.ws = std::make_unique<core::WorkingSet>(*s.reader, *s.cache, *s.loader, core::WorkingSetOptions{});
    for (int i = 0; i < 32 && !(i > 0 && s.ws->stats().settled()); ++i) {
        s.ws->update(views, tf);
        s.loader->waitIdle();
    }
    return s;
}
}  // namespace

TEST(LabelRendering, NoPixelShowsAColourThatIsNotALabels) {
    test::TempDir dir;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.spacing = {0.8, 1.0, 1.5};  // anisotropic: the nearest voxel is taken in index space
    core::JobContext job;
    for (const bool labels : {true, false}) {
        test::MemoryVoxelSource source(g, blocks());
        core::BuildOptions options;
        options.labels = labels;
        core::OctreeBuilder(options).build(source, dir.file(labels ? "labels.hvo" : "image.hvo"), job);
    }
    core::LabelTable table;
    for (const auto& [label, c] : kColours)
        table.set(label, {"label " + std::to_string(label),
                          {std::uint8_t(c.x * 255), std::uint8_t(c.y * 255), std::uint8_t(c.z * 255), 255}});
    const auto tf = core::TransferFunction::forLabels(table, 1.0, 1.0);
    // Every entry is its label's colour, and values between labels take one entry, never a ramp.
    EXPECT_NEAR(tf.entry(3.0).z / tf.entry(3.0).w, 1.0, 1e-9);
    EXPECT_NEAR(tf.entry(2.4).y / tf.entry(2.4).w, 1.0, 1e-9);
    EXPECT_EQ(tf.entry(5.0).w, 0.0) << "a label the table lacks is transparent";
    EXPECT_EQ(tf.entry(10.0).w, 0.0) << "values above the last label are transparent";

    auto labelScene = open(dir.file("labels.hvo"), tf, {});
    ASSERT_TRUE(labelScene.reader->geometry().isLabel);
    const glm::dvec3 centre = labelScene.ws->space().centre();
    std::vector<core::View> views;
    for (const double azimuth : {0.0, 37.0, 118.0, 205.0})
        views.push_back(core::View::orbit(centre, 70.0, azimuth, 25.0, 96, 96));
    labelScene = open(dir.file("labels.hvo"), tf, views);
    auto imageScene = open(dir.file("image.hvo"), tf, views);
    core::RenderSettings rs;
    rs.shading = false;  // colours as the table gives them

    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    int blendedInImage = 0;
    for (const auto& view : views) {
        const auto cpu = core::CpuRayCaster(*labelScene.reader, labelScene.ws->index(), labelScene.ws->slotData(), tf, rs)
                             .render(view);
        const auto gl = gpu.render(*labelScene.reader, labelScene.ws->index(), labelScene.ws->slotBricks(), tf, rs, view);
        const auto image = core::CpuRayCaster(*imageScene.reader, imageScene.ws->index(), imageScene.ws->slotData(), tf, rs)
                               .render(view);
        int coveredCpu = 0, coveredGpu = 0, coveredImage = 0;
        const int foreignCpu = foreignPixels(cpu, coveredCpu), foreignGpu = foreignPixels(gl, coveredGpu);
        blendedInImage += foreignPixels(image, coveredImage);
        const double db = test::psnr(cpu, gl);
        std::printf("view: %d of %d pixels covered, foreign colours CPU %d GPU %d; GPU vs CPU %.1f dB\n",
                    coveredCpu, view.width * view.height, foreignCpu, foreignGpu, db);
        EXPECT_GT(coveredCpu, view.width * view.height / 5);
        EXPECT_EQ(foreignCpu, 0);
        EXPECT_EQ(foreignGpu, 0);
        EXPECT_GT(db, 30.0);
        core::RenderSettings shaded;  // lit: gradients stay trilinear, on both sides alike
        const double dbShaded = test::psnr(
            core::CpuRayCaster(*labelScene.reader, labelScene.ws->index(), labelScene.ws->slotData(), tf, shaded).render(view),
            gpu.render(*labelScene.reader, labelScene.ws->index(), labelScene.ws->slotBricks(), tf, shaded, view));
        EXPECT_GT(dbShaded, 30.0);
    }
    std::printf("the same voxels as an image (trilinear, pre-integrated): %d pixels of blended colour\n", blendedInImage);
    EXPECT_GT(blendedInImage, 20) << "the check would not see a blend";
}

TEST(LabelRendering, LabelsSpanningMoreThanTheTableAreRefused) {
    core::LabelTable table;
    table.set(1, {"one", {255, 0, 0, 255}});
    table.set(5000, {"far", {0, 255, 0, 255}});
    try {
        (void)core::TransferFunction::forLabels(table, 1.0, 1.0);
        FAIL() << "labels 0 to 5000 accepted";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("5000"), std::string::npos) << e.what();
    }
}
