// core::ContentBox: the index box of what a transfer function shows, from the node table alone
// (a bright block in one corner of a dark volume: the box holds its bricks and no others).
#include <gtest/gtest.h>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/ContentBox.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

TEST(ContentBox, HoldsTheBricksTheTransferFunctionShowsAndNoOthers) {
    test::TempDir dir;
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.spacing = {1.0, 2.0, 0.5};
    test::DenseVolume v;
    v.dims = {64, 48, 40};
    for (std::uint32_t k = 0; k < 40; ++k)
        for (std::uint32_t j = 0; j < 48; ++j)
            for (std::uint32_t i = 0; i < 64; ++i)  // a block of 200 at voxels [40, 52) x [4, 12) x [20, 30), 10 elsewhere
                v.values.push_back(i >= 40 && i < 52 && j >= 4 && j < 12 && k >= 20 && k < 30 ? 200.0 : 10.0);
    test::MemoryVoxelSource source(g, v);
    core::BuildOptions options;
    options.brickSize = 8;
    core::JobContext job;
    core::OctreeBuilder(options).build(source, dir.file("v.hvo"), job);
    const auto reader = core::OctreeReader::open(dir.file("v.hvo"));
    const core::TransferFunction bright({{0, glm::dvec4(0.0)}, {100, glm::dvec4(0.0)}, {150, glm::dvec4(1.0)}}, 0, 255, 1.0);
    const auto box = core::ContentBox::of(*reader, bright);
    ASSERT_TRUE(box);
    // The block's bricks of 8 voxels: i 40-55, j 0-15, k 16-31 (the border's samples may reach one brick more).
    EXPECT_LE(box->lo.x, 40.0);
    EXPECT_GE(box->lo.x, 32.0);
    EXPECT_GE(box->hi.x, 52.0);
    EXPECT_LE(box->hi.x, 64.0);
    EXPECT_LE(box->lo.z, 20.0);
    EXPECT_GE(box->hi.z, 30.0);
    EXPECT_LE(box->hi.z - box->lo.z, 24.0) << "the dark rest of the volume counted";
    EXPECT_LE(box->hi.y, 24.0);
    // The corners are the voxels' outer faces in patient space (spacing applied).
    const auto corners = box->corners(reader->geometry());
    EXPECT_NEAR(corners[7].x - corners[0].x, (box->hi.x - box->lo.x) * 1.0, 1e-9);
    EXPECT_NEAR(corners[7].y - corners[0].y, (box->hi.y - box->lo.y) * 2.0, 1e-9);
    // Nothing shown: no box; every value (MIP): the whole volume.
    const core::TransferFunction nothing({{0, glm::dvec4(0.0)}, {255, glm::dvec4(0.0)}}, 0, 255, 1.0);
    EXPECT_FALSE(core::ContentBox::of(*reader, nothing));
    const auto all = core::ContentBox::of(*reader, nothing, true);
    ASSERT_TRUE(all);
    EXPECT_EQ(all->lo, glm::dvec3(0.0));
    EXPECT_EQ(all->hi, glm::dvec3(64, 48, 40));
}
