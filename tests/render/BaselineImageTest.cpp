// Baseline images for each mode on the CT phantom and on the MRI template, rendered by the GPU
// ray caster (llvmpipe in CI) and compared by PSNR on 8-bit sRGB images. On a failure the actual
// image and an amplified difference are written to build/<preset>/test-artifacts/.
// Regenerate after an intended change with HVX_UPDATE_BASELINES=1.
#include <gtest/gtest.h>

#include <png.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <glm/geometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/image/ImageWriter.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
struct Rgb {
    int width = 0, height = 0;
    std::vector<unsigned char> rgba;
};

Rgb readPng(const std::string& path) {
    Rgb img;
    png_image p{};
    p.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&p, path.c_str())) return img;
    p.format = PNG_FORMAT_RGBA;
    img.width = int(p.width);
    img.height = int(p.height);
    img.rgba.resize(PNG_IMAGE_SIZE(p));
    if (!png_image_finish_read(&p, nullptr, img.rgba.data(), 0, nullptr)) img.rgba.clear();
    return img;
}

double psnr8(const Rgb& a, const Rgb& b) {
    if (a.rgba.size() != b.rgba.size() || a.rgba.empty()) return 0.0;
    double se = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) {
        const double d = double(a.rgba[i]) - double(b.rgba[i]);
        se += d * d;
    }
    const double mse = se / double(a.rgba.size());
    return mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
}

const char* modeName(core::RenderSettings::Mode m) {
    switch (m) {
    case core::RenderSettings::Mode::Dvr: return "dvr";
    case core::RenderSettings::Mode::Iso: return "iso";
    case core::RenderSettings::Mode::Mip: return "mip";
    case core::RenderSettings::Mode::MinIp: return "minip";
    case core::RenderSettings::Mode::Average: return "xray";
    }
    return "?";
}

void checkBaselines(const std::string& dataset, const core::OctreeReader& reader, const std::string& preset,
                    double isoPhysical) {
    const auto& g = reader.geometry();
    const auto space = core::OctreeSpace::of(g, reader.brickSize(), reader.levelCount());
    const auto tf = core::TransferFunction::preset(preset, g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                                   space.minSpacing);
    const glm::dvec3 c = space.centre();
    const glm::dvec3 corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const auto view = core::View::orbit(c, glm::length(c - corner) * 3.9, 35.0, 20.0, 128, 128);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    const bool update = std::getenv("HVX_UPDATE_BASELINES") != nullptr;
    const std::string dir = std::string(HVX_SOURCE_DIR) + "/tests/render/baselines/";
    const std::string artifacts = std::string(HVX_BINARY_DIR) + "/test-artifacts/";
    std::filesystem::create_directories(artifacts);
    for (auto mode : {core::RenderSettings::Mode::Dvr, core::RenderSettings::Mode::Iso, core::RenderSettings::Mode::Mip,
                      core::RenderSettings::Mode::MinIp, core::RenderSettings::Mode::Average}) {
        core::BrickCache cache(1u << 30);
        core::BrickLoader loader(reader, cache);
        core::WorkingSetOptions opt;
        opt.cullByTransferFunction = mode == core::RenderSettings::Mode::Dvr;
        core::RenderSettings rs;
        rs.mode = mode;
        rs.isoValue = (isoPhysical - g.rescaleIntercept) / g.rescaleSlope;
        if (mode == core::RenderSettings::Mode::Iso) {
            opt.isosurface = true;
            opt.isoValue = rs.isoValue;
        }
        core::WorkingSet ws(reader, cache, loader, opt);
        ws.converge({view}, tf, {}, 32);
        const auto image = gpu.render(reader, ws.index(), ws.slotBricks(), tf, rs, view);
        const std::string name = dataset + "-" + modeName(mode) + ".png";
        const std::string actualPath = artifacts + name;
        core::ImageWriter::writePng(image, actualPath);
        if (update) {
            std::filesystem::copy_file(actualPath, dir + name, std::filesystem::copy_options::overwrite_existing);
            continue;
        }
        const Rgb want = readPng(dir + name), got = readPng(actualPath);
        ASSERT_FALSE(want.rgba.empty()) << "missing baseline " << dir + name << " (HVX_UPDATE_BASELINES=1 makes it)";
        const double db = psnr8(got, want);
        if (db < 35.0) {
            core::RenderImage diff = image;
            for (std::size_t i = 0; i < diff.rgba.size(); ++i) {
                const auto* w = &want.rgba[i * 4];
                const auto* a = &got.rgba[i * 4];
                const float d = float(std::abs(int(w[0]) - int(a[0])) + std::abs(int(w[1]) - int(a[1])) +
                                      std::abs(int(w[2]) - int(a[2]))) / 255.0f;
                diff.rgba[i] = glm::vec4(glm::vec3(std::min(1.0f, 4.0f * d)), 1.0f);
            }
            core::ImageWriter::writePng(diff, artifacts + "diff-" + name);
        }
        EXPECT_GE(db, 35.0) << name << ": PSNR " << db << " dB; see " << artifacts;
    }
}
}  // namespace

TEST(BaselineImages, CtPhantomEveryMode) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({96, 96, 96}, 3, {400, 400, 400}, 10.0);
    core::JobContext job;
    core::OctreeBuilder(core::BuildOptions{}).build(phantom, dir.file("p.hvo"), job);
    checkBaselines("phantom", *core::OctreeReader::open(dir.file("p.hvo")), "ct-bone", 300.0);
}

TEST(BaselineImages, MriTemplateEveryMode) {
    test::TempDir dir;
    auto source = core::VoxelSourceFactory::open("/usr/share/mricron/templates/ch2better.nii.gz");
    core::JobContext job;
    core::OctreeBuilder(core::BuildOptions{}).build(*source, dir.file("mri.hvo"), job);
    checkBaselines("mri", *core::OctreeReader::open(dir.file("mri.hvo")), "mr-default", 90.0);
}
