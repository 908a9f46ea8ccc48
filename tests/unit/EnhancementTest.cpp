// Boundary enhancement and view-dependent transparency in the CPU reference (the GPU test
// compares the shader against it): on volumes whose gradient is known exactly.
#include <gtest/gtest.h>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/reference/CpuRayCaster.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/WorkingSet.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
// A 24^3 float volume, 1 mm voxels: value = slope · x (a ramp along the patient's x axis).
struct Ramp {
    test::TempDir dir;
    std::unique_ptr<core::OctreeReader> reader;
    explicit Ramp(double slope) {
        core::VolumeGeometry g;
        g.scalarType = core::ScalarType::Float32;
        g.spacing = {1, 1, 1};
        test::DenseVolume v;
        v.dims = {24, 24, 24};
        v.values.resize(24 * 24 * 24);
        for (std::size_t i = 0; i < v.values.size(); ++i) v.values[i] = slope * double(i % 24);
        test::MemoryVoxelSource source(g, v);
        core::JobContext job;
        core::OctreeBuilder({}).build(source, dir.file("ramp.hvo"), job);
        reader = core::OctreeReader::open(dir.file("ramp.hvo"));
    }
    // Alpha of the centre pixel, looking from azimuth `az` (0: along y, 90: along x).
    double centreAlpha(double az, core::RenderSettings rs) {
        // Range 10 per voxel of slope... the TF spans [-1, 9]: a gradient of 1 per voxel is then
        // exactly a full boundary (kBoundaryGradientFraction = 10% of the range per voxel).
        const core::TransferFunction tf({{-1.0, {1, 1, 1, 0.05}}, {9.0, {1, 1, 1, 0.05}}}, -1.0, 9.0, 1.0);
        core::BrickCache cache(1u << 26);
        core::BrickLoader loader(*reader, cache);
        core::WorkingSetOptions opt;
        opt.cullByTransferFunction = false;
        core::WorkingSet ws(*reader, cache, loader, opt);
        const glm::dvec3 c = ws.space().centre();
        const auto view = core::View::orbit(c, 4000.0, az, 0.0, 9, 9);
        ws.converge({view}, tf, {}, 16);
        rs.shading = false;
        return core::CpuRayCaster(*reader, ws.index(), ws.slotData(), tf, rs).render(view).rgba[4 * 9 + 4].a;
    }
};
core::RenderSettings with(double boundary, double viewTransparency) {
    core::RenderSettings rs;
    rs.boundary = boundary;
    rs.viewTransparency = viewTransparency;
    return rs;
}
}  // namespace

TEST(Enhancement, ViewDependentTransparencyClearsBoundariesFacingTheViewerOnly) {
    Ramp ramp(0.1 * (9.0 - -1.0));  // gradient strength exactly 1
    const double plainAlong = ramp.centreAlpha(90, {}), plainAcross = ramp.centreAlpha(0, {});
    ASSERT_GT(plainAlong, 0.5);
    // Looking along the gradient (|n·V| = 1): opacity scaled by 1 - v; v = 1 leaves only the two
    // outermost voxels, whose one-sided gradient is half as strong.
    EXPECT_LT(ramp.centreAlpha(90, with(0, 1)), 0.3 * plainAlong);
    EXPECT_LT(ramp.centreAlpha(90, with(0, 0.5)), plainAlong);
    EXPECT_GT(ramp.centreAlpha(90, with(0, 0.5)), ramp.centreAlpha(90, with(0, 1)));
    // Looking across it (a silhouette, |n·V| = 0): unchanged.
    EXPECT_NEAR(ramp.centreAlpha(0, with(0, 1)), plainAcross, 1e-3);
}

TEST(Enhancement, BoundaryEnhancementKeepsBoundariesAndFadesHomogeneousRegions) {
    Ramp ramp(0.1 * (9.0 - -1.0));
    const double plain = ramp.centreAlpha(0, {});
    EXPECT_NEAR(ramp.centreAlpha(0, with(1, 0)), plain, 1e-3) << "a full-strength boundary keeps its opacity";
    Ramp flat(0.0);  // no gradient anywhere: homogeneous
    ASSERT_GT(flat.centreAlpha(0, {}), 0.5);
    EXPECT_LT(flat.centreAlpha(0, with(1, 0)), 1e-6) << "b = 1 removes homogeneous material";
    EXPECT_NEAR(flat.centreAlpha(0, with(0.5, 0)), 1.0 - std::sqrt(1.0 - flat.centreAlpha(0, {})), 0.02)
        << "b = 0.5 halves each sample's opacity: 1-(1-a/2)^n, close to 1-sqrt(1-alpha) for small a";
}
