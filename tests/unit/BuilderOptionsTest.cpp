#include <gtest/gtest.h>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/octree/OctreeSummary.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"

#include <chrono>
#include <filesystem>

using namespace hvx;

TEST(BuilderOptions, EmptyThresholdFlagsAirNodesWithoutPayloadAndKeepsTheirRange) {
    test::TempDir dir;
    core::PhantomVoxelSource p({96, 96, 64}, 5);
    core::BuildOptions opt;
    opt.brickSize = 8;
    opt.emptyBelow = -500.0;  // air and lungs are "empty"
    core::JobContext job;
    const auto report = core::OctreeBuilder(opt).build(p, dir.file("e.hvo"), job);
    const auto r = core::OctreeReader::open(dir.file("e.hvo"));
    EXPECT_GT(report.emptyNodes, 0u);
    std::size_t empty = 0;
    for (std::uint32_t i = 0; i < r->nodes().size(); ++i) {
        const auto& n = r->nodes()[i];
        const bool isEmpty = n.flags & core::hvo::NodeEmpty;
        EXPECT_EQ(isEmpty, n.maxValue < -500.0f) << "node " << i;
        if (!isEmpty) continue;
        ++empty;
        EXPECT_EQ(n.payloadSize, 0u);
        // An empty node's whole subtree is empty (merged).
        if (n.firstChild != core::hvo::kNoNode)
            for (std::uint32_t c = 0; c < std::uint32_t(__builtin_popcount(n.childMask)); ++c)
                EXPECT_TRUE(r->nodes()[n.firstChild + c].flags & core::hvo::NodeEmpty);
        const auto b = r->readBrick(i);
        EXPECT_TRUE(b.empty);
        EXPECT_EQ(b.value(0, 0, 0), double(std::int16_t(n.minValue)));
    }
    EXPECT_EQ(empty, report.emptyNodes);
    EXPECT_TRUE(r->header().flags & core::hvo::FileEmptyThreshold);

    // Without the threshold the same volume stores every node.
    core::BuildOptions full;
    full.brickSize = 8;
    core::OctreeBuilder(full).build(p, dir.file("f.hvo"), job);
    const auto rf = core::OctreeReader::open(dir.file("f.hvo"));
    EXPECT_LT(r->header().fileSize, rf->header().fileSize);
}

TEST(BuilderOptions, Lossy8BricksStayWithinHalfAQuantisationStep) {
    test::TempDir dir;
    core::PhantomVoxelSource p({48, 40, 36}, 5);
    core::BuildOptions opt;
    opt.brickSize = 8;
    opt.lossy8 = true;
    core::JobContext job;
    const auto report = core::OctreeBuilder(opt).build(p, dir.file("l.hvo"), job);
    const auto r = core::OctreeReader::open(dir.file("l.hvo"));
    EXPECT_GT(report.lossyRmsError, 0.0);
    EXPECT_EQ(r->header().lossyRmsError, report.lossyRmsError);
    EXPECT_LE(report.lossyRmsError, report.lossyMaxError);
    double worst = 0.0;
    for (std::uint32_t id = 0; id < r->nodes().size(); ++id) {
        const auto& n = r->nodes()[id];
        if (n.level != 0) continue;
        const auto b = r->readBrick(id);
        ASSERT_TRUE(b.lossy8);
        ASSERT_EQ(b.type, core::ScalarType::UInt8);
        const double step = (double(b.quantMax) - b.quantMin) / 255.0;
        for (std::uint32_t z = 2; z < 10; ++z)
            for (std::uint32_t y = 2; y < 10; ++y)
                for (std::uint32_t x = 2; x < 10; ++x) {
                    const std::uint32_t i = n.x * 8u + x - 2, j = n.y * 8u + y - 2, k = n.z * 8u + z - 2;
                    if (i >= 48 || j >= 40 || k >= 36) continue;
                    const double err = std::abs(b.value(x, y, z) - p.voxel(i, j, k));
                    ASSERT_LE(err, step / 2 + 1e-3);
                    worst = std::max(worst, err);
                }
    }
    EXPECT_NEAR(worst, report.lossyMaxError, 1e-3);
    const auto text = core::OctreeSummary::of(*r).format(*r);
    EXPECT_NE(text.find("lossy error RMS"), std::string::npos) << text;
}

TEST(BuilderOptions, OutOfRangeOptionsAreRefused) {
    core::BuildOptions o;
    o.brickSize = 2;
    EXPECT_THROW(core::OctreeBuilder{o}, core::Error);
    o = {};
    o.border = 0;
    EXPECT_THROW(core::OctreeBuilder{o}, core::Error);
    o = {};
    o.labels = o.lossy8 = true;
    EXPECT_THROW(core::OctreeBuilder{o}, core::Error);
    o = {};
    o.labels = true;
    o.emptyBelow = 5.0;  // it had dropped every brick of a label-1 map without a word
    EXPECT_THROW(core::OctreeBuilder{o}, core::Error);
}

// A volume whose slices are too large to hold a brick row of them: refused before the layout,
// the file or a slice is allocated (a 30000 x 30000 x 1000 NIfTI had taken 5.9 GB of memory
// before failing; a NRRD of 100000 x 100000 x 1000, 18 GB and 57 s before bad_alloc).
TEST(BuilderOptions, AVolumeWhoseSlicesNoMachineCanHoldIsRefusedBeforeAnythingIsAllocated) {
    test::TempDir dir;
    core::PhantomVoxelSource huge({1000000, 1000000, 2});  // slices of 1.8 TiB
    core::JobContext job;
    const auto start = std::chrono::steady_clock::now();
    const std::string e = test::errorOf([&] { core::OctreeBuilder({}).build(huge, dir.file("huge.hvo"), job); });
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
    EXPECT_EQ(e.rfind(huge.describe() + ": building its octree would hold about ", 0), 0u) << e;
    EXPECT_NE(e.find("slices of 1862.6 GiB, and the records of "), std::string::npos) << e;
    EXPECT_NE(e.find("more than this machine's "), std::string::npos) << e;
    EXPECT_FALSE(std::filesystem::exists(dir.file("huge.hvo")));
}

// A label map whose file rescales its values (a NIfTI scl_slope 3, scl_inter 1): ITK reads
// other labels than the stored ones, so Holovox refuses rather than pick one reading.
TEST(BuilderOptions, ALabelMapWithARescaleIsRefused) {
    test::TempDir dir;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.rescaleSlope = 3;
    g.rescaleIntercept = 1;
    test::DenseVolume v;
    v.dims = {8, 8, 8};
    v.values.assign(512, 1.0);
    test::MemoryVoxelSource source(g, v);
    core::BuildOptions o;
    o.labels = true;
    core::JobContext job;
    const std::string e = test::errorOf([&] { core::OctreeBuilder(o).build(source, dir.file("l.hvo"), job); });
    EXPECT_NE(e.find("rescales them (3 * v + 1"), std::string::npos) << e;
    EXPECT_FALSE(std::filesystem::exists(dir.file("l.hvo")));
    g.rescaleSlope = 1;
    g.rescaleIntercept = 0;
    test::MemoryVoxelSource plain(g, v);
    EXPECT_NO_THROW(core::OctreeBuilder(o).build(plain, dir.file("l.hvo"), job));
}

// Labels are held as 32-bit floats when the file's integers are wider: beyond 2^24 two classes
// would become one (16777217 reads as 16777216), so such a map is refused and nothing is written.
TEST(BuilderOptions, LabelsBeyondWhatAFloatHoldsExactlyAreRefused) {
    test::TempDir dir;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Float32;
    test::DenseVolume v;
    v.dims = {8, 8, 8};
    v.values.assign(512, 0.0);
    v.values[3] = 16777215.0;  // the largest kept
    core::BuildOptions o;
    o.labels = true;
    core::JobContext job;
    test::MemoryVoxelSource fits(g, v);
    EXPECT_NO_THROW(core::OctreeBuilder(o).build(fits, dir.file("ok.hvo"), job));
    v.values[7] = -16777216.0;
    test::MemoryVoxelSource beyond(g, v);
    const std::string e = test::errorOf([&] { core::OctreeBuilder(o).build(beyond, dir.file("l.hvo"), job); });
    EXPECT_NE(e.find("its labels reach 16777216 in magnitude"), std::string::npos) << e;
    EXPECT_FALSE(std::filesystem::exists(dir.file("l.hvo")));
}

TEST(BuilderOptions, SummaryCountsLevelsNodesAndCompression) {
    test::TempDir dir;
    core::PhantomVoxelSource p({100, 60, 20}, 5);
    core::BuildOptions opt;
    opt.brickSize = 16;
    core::JobContext job;
    core::OctreeBuilder(opt).build(p, dir.file("s.hvo"), job);
    const auto r = core::OctreeReader::open(dir.file("s.hvo"));
    const auto s = core::OctreeSummary::of(*r);
    ASSERT_EQ(s.levels.size(), 4u);  // 7x4x2, 4x2x1, 2x1x1, 1x1x1 nodes
    EXPECT_EQ(s.levels[0].nodeCount, 7u * 4u * 2u);
    EXPECT_EQ(s.levels[3].nodeCount, 1u);
    EXPECT_EQ(s.nodeCount, r->nodes().size());
    EXPECT_EQ(s.fileBytes, std::filesystem::file_size(dir.file("s.hvo")));
    EXPECT_GT(double(s.rawBrickBytes) / double(r->header().payloadBytes), 1.0);
}
