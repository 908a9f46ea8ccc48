// The GPU brick pool keeps each volume's stored type (R8, R16, R32F) and still gives back the
// exact stored values: every scalar type and lossy 8-bit bricks render as the CPU reference does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/reference/CpuRayCaster.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
// Largest absolute difference of the grey MIP/MinIP images, in stored units.
/// A projection's window fraction from the frame's light (its sRGB code, IEC 61966-2-1).
double windowFraction(float light) {
    const double l = double(light);
    return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

double worstStoredError(const core::RenderImage& a, const core::RenderImage& b, double range) {
    double worst = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i)
        worst = std::max(worst, std::abs(windowFraction(a.rgba[i].r) - windowFraction(b.rgba[i].r)));
    return worst * range;
}

struct Case {
    core::ScalarType type;
    bool lossy;
    const char* name;
};
}  // namespace

TEST(GpuBrickPool, EveryStoredTypeAndLossyBricksGiveTheCpuReferenceValues) {
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu(render::GpuRayCaster::PoolPrecision::Native);
    render::GpuRayCaster floatPool(render::GpuRayCaster::PoolPrecision::Float);
    for (const Case c : {Case{core::ScalarType::UInt8, false, "uint8 (R8)"}, Case{core::ScalarType::Int16, false, "int16 (R16)"},
                         Case{core::ScalarType::UInt16, false, "uint16 (R16)"},
                         Case{core::ScalarType::Float32, false, "float32 (R32F)"},
                         Case{core::ScalarType::Int16, true, "int16 lossy 8-bit"}}) {
        test::TempDir dir;
        core::VolumeGeometry g;
        g.scalarType = c.type;
        g.spacing = {1.0, 1.0, 1.0};
        // Extremes of the type included: int16's -32768 (padding) must stay exact.
        test::MemoryVoxelSource source(g, test::randomVolume({40, 36, 30}, c.type, 7));
        core::BuildOptions options;
        options.lossy8 = c.lossy;
        core::JobContext job;
        core::OctreeBuilder(options).build(source, dir.file("v.hvo"), job);
        const auto reader = core::OctreeReader::open(dir.file("v.hvo"));
        const auto& rg = reader->geometry();
        const double range = rg.valueMax - rg.valueMin;
        const auto tf = core::TransferFunction::preset("mip-ramp", rg.valueMin, rg.valueMax, 1, 0, 1.0);
        core::BrickCache cache(1u << 28);
        core::BrickLoader loader(*reader, cache);
        core::WorkingSetOptions opt;
        opt.cullByTransferFunction = false;
        core::WorkingSet ws(*reader, cache, loader, opt);
        const glm::dvec3 centre = ws.space().centre();
        const auto view = core::View::orbit(centre, 200.0, 20.0, 10.0, 48, 40);
        for (int i = 0; i < 32 && !(i > 0 && ws.stats().settled()); ++i) {
            ws.update({view}, tf);
            loader.waitIdle();
        }
        for (auto mode : {core::RenderSettings::Mode::Mip, core::RenderSettings::Mode::MinIp}) {
            core::RenderSettings rs;
            rs.mode = mode;
            const auto want = core::CpuRayCaster(*reader, ws.index(), ws.slotData(), tf, rs).render(view);
            const auto got = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, rs, view);
            const double err = worstStoredError(got, want, range);
            std::printf("%-18s %s: worst difference %.4g stored units of a range of %.6g\n", c.name,
                        mode == core::RenderSettings::Mode::Mip ? "MIP  " : "MinIP", err, range);
            // Filtering weights differ in the last bits between the texture unit and the CPU;
            // the values themselves must be the stored ones. Texture units filter 8-bit texels
            // with 8-bit weights (llvmpipe's unorm8 path, and GPUs), so on this noise volume, where
            // neighbours differ by up to the whole range, an R8 sample may be off by range/256.
            const bool eightBit = c.type == core::ScalarType::UInt8;
            EXPECT_LT(err, (eightBit ? 1.0 / 200.0 : 1e-4) * range) << c.name;
            const auto asFloat = floatPool.render(*reader, ws.index(), ws.slotBricks(), tf, rs, view);
            EXPECT_LT(worstStoredError(asFloat, want, range), 1e-4 * range) << c.name << " in an R32F pool";
        }
        EXPECT_EQ(gpu.poolBytes() * 4, floatPool.poolBytes() * core::scalarSize(c.type)) << "pool sized by type";
    }
}
