#include <gtest/gtest.h>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/ReferenceOctree.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
struct Case {
    const char* name;
    std::array<std::uint32_t, 3> dims;
    core::ScalarType type;
    std::uint32_t brick, border;
    core::hvo::Codec codec;
    int labels;
};

class OctreeRoundTrip : public ::testing::TestWithParam<Case> {};

core::VolumeGeometry obliqueGeometry(core::ScalarType type) {
    core::VolumeGeometry g;
    g.scalarType = type;
    g.spacing = {0.7, 0.9, 2.5};
    g.origin = {-120.5, 33.25, 401.0};
    const double c = std::cos(0.3), s = std::sin(0.3);
    g.direction = glm::dmat3(glm::dvec3(c, s, 0), glm::dvec3(-s, c, 0), glm::dvec3(0, 0, 1));
    g.rescaleSlope = 2.0;
    g.rescaleIntercept = -1024.0;
    g.modality = "CT";
    return g;
}
}  // namespace

TEST_P(OctreeRoundTrip, EveryBrickSampleMatchesTheFilteredPyramid) {
    const Case& c = GetParam();
    test::TempDir dir;
    auto g = obliqueGeometry(c.type);
    if (c.labels > 0) g.rescaleSlope = 1.0, g.rescaleIntercept = 0.0;  // a label map's classes are its stored values
    test::MemoryVoxelSource src(g, test::randomVolume(c.dims, c.type, 42, c.labels));
    core::BuildOptions opt;
    opt.brickSize = c.brick;
    opt.border = c.border;
    opt.codec = c.codec;
    opt.labels = c.labels > 0;
    core::JobContext job;
    const auto report = core::OctreeBuilder(opt).build(src, dir.file("v.hvo"), job);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"v.hvo"});

    const auto reader = core::OctreeReader::open(dir.file("v.hvo"));
    EXPECT_EQ(report.nodeCount, reader->nodes().size());
    const auto& rg = reader->geometry();
    EXPECT_EQ(rg.dims, c.dims);
    EXPECT_EQ(rg.spacing, g.spacing);
    EXPECT_EQ(rg.origin, g.origin);
    EXPECT_EQ(rg.direction, g.direction);
    EXPECT_EQ(rg.scalarType, c.type);
    EXPECT_EQ(rg.rescaleSlope, g.rescaleSlope);
    EXPECT_EQ(rg.rescaleIntercept, g.rescaleIntercept);
    EXPECT_EQ(rg.modality, "CT");
    EXPECT_EQ(rg.isLabel, c.labels > 0);
    const auto& vals = src.values().values;
    EXPECT_EQ(rg.valueMin, *std::min_element(vals.begin(), vals.end()));
    EXPECT_EQ(rg.valueMax, *std::max_element(vals.begin(), vals.end()));

    const auto pyramid = test::referencePyramid(src.values(), reader->levelCount(), c.type, c.labels > 0);
    test::expectOctreeMatches(*reader, pyramid);
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, OctreeRoundTrip,
    ::testing::Values(Case{"nonPow2Int16Zstd", {45, 37, 29}, core::ScalarType::Int16, 8, 2, core::hvo::Codec::Zstd, 0},
                      Case{"oneVoxel", {1, 1, 1}, core::ScalarType::UInt8, 32, 2, core::hvo::Codec::Zstd, 0},
                      Case{"slab1xNxM", {1, 17, 33}, core::ScalarType::UInt16, 8, 2, core::hvo::Codec::Lz4, 0},
                      Case{"lineNx1x1", {70, 1, 1}, core::ScalarType::Int16, 8, 3, core::hvo::Codec::None, 0},
                      Case{"float32", {20, 21, 22}, core::ScalarType::Float32, 8, 2, core::hvo::Codec::Zstd, 0},
                      Case{"wideBorder", {33, 9, 40}, core::ScalarType::UInt8, 4, 4, core::hvo::Codec::Zstd, 0},
                      Case{"labelsMode", {30, 22, 18}, core::ScalarType::UInt8, 8, 2, core::hvo::Codec::Zstd, 5}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(OctreeBorder, FacesEdgesAndCornersReplicateNeighboursAndClampAtTheVolumeEdge) {
    // A volume whose value encodes its coordinates makes every border sample checkable.
    test::TempDir dir;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::Float32;
    test::DenseVolume v;
    v.dims = {24, 24, 24};
    for (std::uint32_t k = 0; k < 24; ++k)
        for (std::uint32_t j = 0; j < 24; ++j)
            for (std::uint32_t i = 0; i < 24; ++i) v.values.push_back(i + 100.0 * j + 10000.0 * k);
    test::MemoryVoxelSource src(g, v);
    core::BuildOptions opt;
    opt.brickSize = 8;
    opt.border = 2;
    core::JobContext job;
    core::OctreeBuilder(opt).build(src, dir.file("c.hvo"), job);
    const auto r = core::OctreeReader::open(dir.file("c.hvo"));
    const std::uint32_t e = r->brickEdge();  // 12
    const auto leaf = [&](int x, int y, int z) {
        for (std::uint32_t id = 0; id < r->nodes().size(); ++id) {
            const auto& n = r->nodes()[id];
            if (n.level == 0 && n.x == x && n.y == y && n.z == z) return r->readBrick(id);
        }
        throw std::runtime_error("no such leaf");
    };
    // The centre leaf (1,1,1): border samples come from its 26 neighbours.
    const auto centre = leaf(1, 1, 1);
    EXPECT_EQ(centre.value(0, 0, 0), 6 + 600 + 60000);               // corner (-2,-2,-2) from voxel 6
    EXPECT_EQ(centre.value(e - 1, e - 1, e - 1), 17 + 1700 + 170000);  // opposite corner
    EXPECT_EQ(centre.value(0, 5, 5), 6 + 1100 + 110000);              // -x face
    EXPECT_EQ(centre.value(e - 1, 0, 5), 17 + 600 + 110000);          // +x/-y edge
    // The corner leaf (0,0,0): outside the volume the edge voxel is replicated.
    const auto corner = leaf(0, 0, 0);
    EXPECT_EQ(corner.value(0, 0, 0), 0);
    EXPECT_EQ(corner.value(1, 2, 0), 0);
    EXPECT_EQ(corner.value(2, 0, 3), 0 + 0 + 10000);
    EXPECT_EQ(corner.value(e - 1, e - 1, 0), 9 + 900);
}

TEST(OctreeRoundTrip, PhantomLeavesEqualTheSourceVoxels) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({67, 51, 40}, 7);
    core::BuildOptions opt;
    opt.brickSize = 16;
    core::JobContext job;
    core::OctreeBuilder(opt).build(phantom, dir.file("p.hvo"), job);
    const auto r = core::OctreeReader::open(dir.file("p.hvo"));
    for (std::uint32_t id = 0; id < r->nodes().size(); ++id) {
        const auto& n = r->nodes()[id];
        if (n.level != 0) continue;
        const auto b = r->readBrick(id);
        for (std::uint32_t z = 2; z < 18; ++z)
            for (std::uint32_t y = 2; y < 18; ++y)
                for (std::uint32_t x = 2; x < 18; ++x) {
                    const std::uint32_t i = n.x * 16u + x - 2, j = n.y * 16u + y - 2, k = n.z * 16u + z - 2;
                    if (i >= 67 || j >= 51 || k >= 40) continue;
                    ASSERT_EQ(b.value(x, y, z), phantom.voxel(i, j, k)) << i << "," << j << "," << k;
                }
    }
}
