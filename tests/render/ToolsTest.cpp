// The illustrative tools on llvmpipe: each tool and three together on the GPU equal the CPU
// reference; the clip plane seen face-on equals a plain cut; a band over the whole range and
// MImDA with gamma = 0 equal plain DVR.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <glm/geometric.hpp>

#include "core/appearance/Enhancers.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/image/ImageWriter.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/OctreeScene.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
using test::psnr;

double maxDifference(const core::RenderImage& a, const core::RenderImage& b) {
    double m = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i)
        for (int c = 0; c < 4; ++c) m = std::max(m, double(std::abs(a.rgba[i][c] - b.rgba[i][c])));
    return m;
}

struct Scene : test::OctreeScene {
    core::View view;
    explicit Scene(core::VoxelSource& source, double az = 30, double el = 15) : OctreeScene(source) {
        view = core::View::orbit(centre(), 1100.0, az, el, 96, 80);
    }
    void settle(const core::TransferFunction& tf) { ws->converge({view}, tf, {}, 32); }
    core::RenderImage cpu(const core::TransferFunction& tf, const core::RenderSettings& rs) {
        return core::CpuRayCaster(*reader, ws->index(), ws->slotData(), tf, rs).render(view);
    }
};

/// The CT phantom with soft-tissue DVR, its cut settled, and a GPU ray caster: the scene of
/// the tests that hold the GPU against the CPU reference.
struct PhantomScene {
    core::PhantomVoxelSource phantom;
    Scene s;
    core::TransferFunction tf;
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    explicit PhantomScene(double az = 30, double el = 15)
        : phantom({96, 96, 80}, 3, {400, 400, 400}, 10.0), s(phantom, az, el),
          tf(core::TransferFunction::preset("ct-soft-tissue", s.reader->geometry().valueMin,
                                            s.reader->geometry().valueMax, 1, 0, 4.0)) {
        s.settle(tf);
    }
};

core::ToolSet toolsFor(int bits, const glm::dvec3& centre, double lo, double hi) {
    core::ToolSet t;
    t.clip.enabled = bits & core::ToolSet::ClipBit;
    t.clip.normal = {0, -1, 0.3};
    t.clip.offset = glm::dot(glm::normalize(t.clip.normal), centre) * -1.0 * glm::length(t.clip.normal);
    t.focal.enabled = bits & core::ToolSet::FocalBit;
    t.focal.centre = centre;
    t.focal.radii = {70, 60, 90};
    t.focal.q = 4;  // a cylinder, turned
    t.focal.rotationDegrees = {30, 0, 20};
    t.context.enabled = bits & core::ToolSet::ContextBit;
    t.context.centre = centre + glm::dvec3(30, 0, 0);
    t.context.radius = 80;
    t.band.enabled = bits & core::ToolSet::BandBit;
    t.band.band = {lo + 0.5 * (hi - lo), lo + 0.55 * (hi - lo), hi, hi};
    t.mimda.enabled = bits & core::ToolSet::MimdaBit;
    return t;
}
}  // namespace

TEST(Tools, EachToolAndThreeTogetherOnTheGpuEqualTheCpuReference) {
    PhantomScene scene;
    Scene& s = scene.s;
    const auto& g = s.reader->geometry();
    const core::TransferFunction& tf = scene.tf;
    render::GpuRayCaster& gpu = scene.gpu;
    using T = core::ToolSet;
    const int combos[] = {T::ClipBit, T::FocalBit, T::ContextBit, T::BandBit | T::MimdaBit, T::ClipBit | T::FocalBit | T::BandBit,
                          T::ClipBit | T::ContextBit | T::BandBit | T::MimdaBit};
    const auto plain = s.cpu(tf, {});
    for (int bits : combos) {
        core::RenderSettings rs;
        rs.tools = toolsFor(bits, s.centre(), g.valueMin, g.valueMax);
        const auto want = s.cpu(tf, rs);
        const auto got = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, rs, s.view);
        const double db = psnr(got, want);
        std::printf("tools %2d: GPU vs CPU %.1f dB (tool vs plain DVR %.1f dB)\n", bits, db, psnr(want, plain));
        if (db < 75.0) {
            std::filesystem::create_directories(HVX_BINARY_DIR "/test-artifacts");
            core::ImageWriter::write(got, HVX_BINARY_DIR "/test-artifacts/tools-gpu-" + std::to_string(bits) + ".png");
            core::ImageWriter::write(want, HVX_BINARY_DIR "/test-artifacts/tools-cpu-" + std::to_string(bits) + ".png");
        }
        EXPECT_GT(db, 75.0) << "tools " << bits << " (measured 84.4 to 98.7 dB; the bar is 9.4 dB under)";
        EXPECT_LT(psnr(want, plain), 60.0) << "tools " << bits << " change the image";
    }
}

TEST(Tools, ClipPlaneSeenFaceOnEqualsAPlainCut) {
    // A volume cut by hand: everything with z > 0 (superior half) set to air.
    core::PhantomVoxelSource phantom({64, 64, 64}, 3, {300, 300, 300}, 0.0);
    core::VolumeGeometry g = phantom.geometry();
    test::DenseVolume whole, cut;
    whole.dims = cut.dims = {64, 64, 64};
    std::vector<std::int16_t> slice(64 * 64);
    for (std::uint32_t z = 0; z < 64; ++z) {
        phantom.readSlices(z, 1, slice.data());
        for (auto v : slice) whole.values.push_back(v);
    }
    cut.values = whole.values;
    const glm::dmat4 toPatient = g.indexToPatient();
    // The plane between slices 29 and 30: the upper bricks (slices 32-63) lie wholly beyond it.
    const glm::dvec3 centre(toPatient * glm::dvec4(31.5, 31.5, 29.5, 1));
    for (std::size_t k = 0; k < 64; ++k)
        if (glm::dvec3(toPatient * glm::dvec4(0, 0, double(k), 1)).z > centre.z)
            for (std::size_t i = 0; i < 64 * 64; ++i) cut.values[k * 64 * 64 + i] = -1024;
    test::MemoryVoxelSource wholeSource(g, whole), cutSource(g, cut);
    Scene a(wholeSource, 0, 89.9), b(cutSource, 0, 89.9);  // seen from above: face-on to the plane z = centre
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", -1024, 3071, 1, 0, 4.0);
    a.settle(tf);
    b.settle(tf);
    core::RenderSettings rs;
    rs.tools.clip.enabled = true;
    rs.tools.clip.normal = {0, 0, 1};
    rs.tools.clip.offset = -centre.z;
    rs.tools.clip.thickness = 0;  // no emphasis slab: a plain cut
    const auto tool = a.cpu(tf, rs);
    const auto plain = b.cpu(tf, {});
    // Seen face-on, the cut-away side is hidden from every ray: its bricks need not be loaded.
    ASSERT_TRUE(rs.tools.clipHides(a.view));
    const std::size_t fullCut = a.ws->stats().cutNodes;
    a.ws->options().clip = true;
    a.ws->options().clipPlane = rs.tools.keptHalfSpace();
    a.settle(tf);
    EXPECT_LT(a.ws->stats().cutNodes, fullCut);
    EXPECT_GT(psnr(a.cpu(tf, rs), tool), 60.0) << "skipping the hidden bricks changes nothing";
    rs.tools.clip.normal = {1, 0, 0};  // seen edge-on: the far side shows as context
    EXPECT_FALSE(rs.tools.clipHides(a.view));
    const double db = psnr(tool, plain);
    std::printf("face-on clip plane vs the volume cut by hand: %.1f dB\n", db);
    EXPECT_GT(db, 35.0) << "they differ only within half a voxel of the plane";
}

TEST(Tools, AFullRangeBandAndMimdaWithGammaZeroEqualPlainDvr) {
    core::PhantomVoxelSource phantom({80, 80, 64}, 3, {400, 400, 400}, 10.0);
    Scene s(phantom);
    const auto& g = s.reader->geometry();
    const auto tf = core::TransferFunction::preset("ct-bone", g.valueMin, g.valueMax, 1, 0, 4.0);
    s.settle(tf);
    const auto plain = s.cpu(tf, {});
    core::RenderSettings band;
    band.tools.band.enabled = true;
    band.tools.band.band = {g.valueMin - 1, g.valueMin - 1, g.valueMax + 1, g.valueMax + 1};
    core::RenderSettings mimda;
    mimda.tools.mimda.enabled = true;
    mimda.tools.mimda.gamma = 0.0;
    for (const auto* rs : {&band, &mimda}) {
        const auto img = s.cpu(tf, *rs);
        const double diff = maxDifference(img, plain);
        std::printf("%s: largest difference from plain DVR %.2g\n", rs == &band ? "full-range band" : "MImDA gamma 0", diff);
        EXPECT_LT(diff, 1e-4) << "float rounding only";
    }
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const auto gpuPlain = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, {}, s.view);
    const auto gpuMimda = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, mimda, s.view);
    EXPECT_LT(maxDifference(gpuMimda, gpuPlain), 1e-4) << "the GPU's MImDA variant with gamma 0 is plain DVR";
}

// The crop box on the GPU equals the CPU reference in every mode, for a box seen at a slant
// and for one that cuts through the volume's middle.
TEST(Tools, CropBoxOnTheGpuEqualsTheCpuReference) {
    core::PhantomVoxelSource phantom({96, 96, 80}, 3, {400, 400, 400}, 10.0);
    Scene s(phantom);
    const auto& g = s.reader->geometry();
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", g.valueMin, g.valueMax, 1, 0, 4.0);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    s.ws->options().cullByTransferFunction = false;  // MIP and iso need every brick
    s.settle(tf);
    const auto plain = s.cpu(tf, {});
    for (const auto& [lo, hi] : std::vector<std::pair<glm::dvec3, glm::dvec3>>{{{0.1, 0.2, 0.0}, {0.6, 1.0, 0.7}},
                                                                              {{0.0, 0.0, 0.5}, {1.0, 1.0, 1.0}}})
        for (auto mode : {core::RenderSettings::Mode::Dvr, core::RenderSettings::Mode::Mip, core::RenderSettings::Mode::Iso}) {
            core::RenderSettings rs;
            rs.mode = mode;
            rs.isoValue = 0.5 * (g.valueMin + g.valueMax);
            rs.crop.min = lo;
            rs.crop.max = hi;
            s.ws->options().crop = rs.crop;
            s.settle(tf);
            const auto want = s.cpu(tf, rs);
            const auto got = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, rs, s.view);
            const double db = psnr(got, want);
            std::printf("crop %.1f,%.1f,%.1f-%.1f,%.1f,%.1f mode %d: GPU vs CPU %.1f dB (vs uncropped %.1f dB)\n", lo.x,
                        lo.y, lo.z, hi.x, hi.y, hi.z, int(mode), db, psnr(want, plain));
            EXPECT_GT(db, 75.0) << "mode " << int(mode);
            if (mode == core::RenderSettings::Mode::Dvr) EXPECT_LT(psnr(want, plain), 40.0) << "the crop changes the image";
        }
}

// Where the tools leave nothing to see (core::glsl::hvxHidden), the GPU skips the samples'
// gradients and enhancers; the CPU reference runs the whole chain on them. Each tool is set up
// so that it hides much of the frame: the focal probe's focus cone over the middle of the view,
// the clip plane face-on, the context probe seen across its axis. Where the hidden samples lie at
// an end of a ray or in one stretch of it, the GPU does not step through them at all
// (hvxVisibleSpan, hvxHiddenGap).
TEST(Tools, SkippingWhatTheToolsHideLeavesTheImageAsTheCpuReferenceDrawsIt) {
    PhantomScene scene(0, 0);
    Scene& s = scene.s;
    const core::TransferFunction& tf = scene.tf;
    render::GpuRayCaster& gpu = scene.gpu;
    const glm::dvec3 forward = glm::normalize(s.view.target - s.view.eye);
    std::vector<std::pair<const char*, core::ToolSet>> cases(5);
    cases[0].first = "focal probe, wide focus cone";
    cases[0].second.focal.enabled = true;
    cases[0].second.focal.centre = s.centre();
    cases[0].second.focal.radii = glm::dvec3(60);
    cases[0].second.focal.rho = 0.9;
    cases[1].first = "clip plane face-on";
    cases[1].second.clip.enabled = true;
    cases[1].second.clip.normal = -forward;  // the cut-away half faces the viewer
    cases[1].second.clip.offset = glm::dot(forward, s.centre());
    cases[2].first = "context probe across its axis";
    cases[2].second.context.enabled = true;
    cases[2].second.context.centre = s.centre();
    cases[2].second.context.radius = 90;
    cases[2].second.context.axis = glm::normalize(glm::cross(forward, s.view.up));
    cases[3].first = "all three";
    cases[3].second.focal = cases[0].second.focal;
    cases[3].second.clip = cases[1].second.clip;
    cases[3].second.clip.offset += 30;
    cases[3].second.context = cases[2].second.context;
    cases[3].second.context.centre += glm::dvec3(40, 0, 0);
    // without the focal probe, rays start at the cut and jump over the context probe's front half
    cases[4].first = "clip plane face-on and context probe across its axis";
    cases[4].second.clip = cases[3].second.clip;
    cases[4].second.context = cases[3].second.context;
    const auto plain = s.cpu(tf, {});
    for (const auto& [name, tools] : cases) {
        core::RenderSettings rs;
        rs.tools = tools;
        const auto want = s.cpu(tf, rs);
        const auto got = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, rs, s.view);
        const double db = psnr(got, want);
        std::printf("%s: GPU vs CPU %.1f dB (vs plain DVR %.1f dB)\n", name, db, psnr(want, plain));
        EXPECT_GT(db, 80.0) << name;
        EXPECT_LT(psnr(want, plain), 40.0) << name << " changes the image";
    }
}

// Focus and context sampling (ToolSet::FocalProbe::contextStep): outside the focal probe's
// bounding sphere, where it draws only the ghosted context, rays step several samples at a time.
// The GPU still equals the CPU reference; a step of 1 is the dense march; and every pixel whose
// ray lies in the focus cone (hTheta = 0: all it shows is inside the probe) is the dense
// march's, bit for bit.
TEST(Tools, TheFocalProbesContextIsSampledSparselyAndItsFocusExactly) {
    PhantomScene scene;
    Scene& s = scene.s;
    const auto& g = s.reader->geometry();
    const core::TransferFunction& tf = scene.tf;
    render::GpuRayCaster& gpu = scene.gpu;
    core::RenderSettings sparse, dense;
    sparse.tools.focal.enabled = true;
    sparse.tools.focal.centre = s.centre() + glm::dvec3(20, 0, 0);
    sparse.tools.focal.radii = glm::dvec3(100);
    sparse.tools.focal.rho = 0.8;
    dense.tools = sparse.tools;
    dense.tools.focal.contextStep = 1;
    ASSERT_EQ(sparse.tools.focal.contextStep, 3) << "the default context step";
    const auto gpuSparse = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, sparse, s.view);
    const auto gpuDense = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, dense, s.view);
    const auto cpuSparse = s.cpu(tf, sparse), cpuDense = s.cpu(tf, dense);
    const double dbSparse = psnr(gpuSparse, cpuSparse), dbDense = psnr(gpuDense, cpuDense);
    const double dbStep = psnr(cpuSparse, cpuDense);
    std::printf("GPU vs CPU: context step 3 %.1f dB, step 1 %.1f dB; step 3 vs step 1 (CPU) %.1f dB\n", dbSparse, dbDense,
                dbStep);
    EXPECT_GT(dbSparse, 80.0);
    EXPECT_GT(dbDense, 80.0);
    EXPECT_LT(dbStep, 80.0) << "the context is sampled more sparsely";
    EXPECT_GT(dbStep, 25.0) << "the ghosted context keeps its look (measured 33.0 dB)";
    // The focus cone's pixels, found as the ray caster finds them (hvxFocalAngle).
    const auto packed = core::packTools(sparse.tools, glm::dvec4(0.3, 0.7, 0.2, 20));
    std::size_t focus = 0, equal = 0;
    float cpuWorst = 0.0f;
    for (int y = 0; y < s.view.height; ++y)
        for (int x = 0; x < s.view.width; ++x) {
            glm::dvec3 o, d;
            s.view.ray(x, double(y), o, d);
            if (core::glsl::hvxFocalAngle(packed, glm::vec3(o), glm::vec3(d)) > 0.0f) continue;
            const std::size_t i = std::size_t(y) * std::size_t(s.view.width) + std::size_t(x);
            ++focus;
            equal += gpuSparse.rgba[i] == gpuDense.rgba[i];
            for (int c = 0; c < 4; ++c) cpuWorst = std::max(cpuWorst, std::abs(cpuSparse.rgba[i][c] - cpuDense.rgba[i][c]));
        }
    std::printf("focus cone: %zu pixels, %zu the same at both steps on the GPU; on the CPU at most %.2g apart\n", focus,
                equal, double(cpuWorst));
    EXPECT_GT(focus, std::size_t(300));
    EXPECT_EQ(equal, focus) << "the GPU starts these rays on the probe: the same samples";
    // The CPU reference marches the hidden context before the probe too, in steps of 3·dt where
    // the dense march adds dt three times: its samples in the focus move by float rounding only.
    EXPECT_LT(cpuWorst, 2e-3f);
    // Without the focal probe its context step changes nothing: the other tools' variants do
    // not carry the stepping.
    core::RenderSettings other;
    other.tools = toolsFor(core::ToolSet::ContextBit | core::ToolSet::ClipBit, s.centre(), g.valueMin, g.valueMax);
    other.tools.focal.contextStep = 1;
    const auto one = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, other, s.view);
    other.tools.focal.contextStep = 8;
    const auto eight = gpu.render(*s.reader, s.ws->index(), s.ws->slotBricks(), tf, other, s.view);
    EXPECT_EQ(maxDifference(one, eight), 0.0);
}
