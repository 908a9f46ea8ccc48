// The split-voxel .hvo file (thesis §4.4, version 2 of the format): what it holds, where it is
// refused, and its streamed build equal to the levels fitted with the whole volume in memory.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include <glm/geometric.hpp>

#include <cstddef>
#include <fstream>

#include "core/base/Error.h"
#include "core/octree/BrickCodec.h"
#include "core/octree/OctreeReader.h"
#include "core/octree/SplitVoxelGrid.h"
#include "core/octree/SplitVoxelOctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include <cstring>
#include <tuple>
#include "tests/support/TempDir.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/SplitVoxelScene.h"

using namespace hvx;
using test::degreesBetween;

// The split-voxel .hvo (version 2): every node's brick holds the cells of its level (cells past
// the grid repeat its last ones) as the hierarchy made them, every node's range covers its
// subtree, the header says the source's dimensions; readers that draw voxels refuse it by
// default, a newer version is named, and a version 1 header marked split is refused.
TEST(SplitVoxelOctree, FileHoldsTheLevelsAndIsRefusedWhereVoxelsAreExpected) {
    test::TempDir dir;
    test::DenseVolume dense;
    dense.dims = {40, 36, 30};
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, 1.0, 0.5));
    for (std::uint32_t k = 0; k < 30; ++k)
        for (std::uint32_t j = 0; j < 36; ++j)
            for (std::uint32_t i = 0; i < 40; ++i)
                dense.values.push_back(glm::dot(n, glm::dvec3(i, j, k) - glm::dvec3(20, 18, 15)) >= 0 ? 3.0 : 1.0);
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.isLabel = true;
    g.spacing = {0.5, 0.7, 1.2};
    g.origin = {-10, 20, 30};
    test::MemoryVoxelSource source(g, dense);
    core::BuildOptions b;
    b.brickSize = 8;
    core::SplitVoxelOptions o;
    core::JobContext job;
    core::SplitVoxelOctreeBuilder(b, o).build(source, dir.file("s.hvo"), job);
    const auto reader = core::OctreeReader::open(dir.file("s.hvo"), true);
    ASSERT_TRUE(reader->splitVoxels());
    EXPECT_EQ(reader->header().version, 2u);  // version 1 readers refuse it: "unsupported version 2"
    EXPECT_EQ(reader->sourceDims(), (std::array<std::uint32_t, 3>{40, 36, 30}));
    EXPECT_EQ(reader->geometry().dims, (std::array<std::uint32_t, 3>{20, 18, 15}));
    EXPECT_EQ(reader->geometry().spacing, glm::dvec3(1.0, 1.4, 2.4));
    // Cell (0,0,0)'s centre lies halfway between voxels 0 and 1.
    EXPECT_LT(glm::length(reader->geometry().origin - glm::dvec3(-9.75, 20.35, 30.6)), 1e-9);
    EXPECT_TRUE(reader->geometry().isLabel);

    o.labels = true;
    std::vector<core::SplitVoxelGrid> levels{core::SplitVoxelGrid::build(source, o, job)};
    while (int(levels.size()) < reader->levelCount()) levels.push_back(levels.back().coarser(o, job));
    for (std::uint32_t id = 0; id < reader->nodes().size(); ++id) {
        const auto& rec = reader->nodes()[id];
        const auto brick = reader->readBrick(id);
        ASSERT_TRUE(brick.splitVoxels);
        const auto& level = levels[rec.level];
        const auto& d = level.dims();
        for (std::uint32_t z = 0; z < 8; ++z)
            for (std::uint32_t y = 0; y < 8; ++y)
                for (std::uint32_t x = 0; x < 8; ++x) {
                    const auto want = level.at(std::min(rec.x * 8 + x, d[0] - 1), std::min(rec.y * 8 + y, d[1] - 1),
                                               std::min(rec.z * 8 + z, d[2] - 1));
                    const auto got = brick.cell(x, y, z);
                    ASSERT_EQ(got.front, want.front);
                    ASSERT_EQ(got.back, want.back);
                    ASSERT_EQ(got.isUniform(), want.isUniform());
                    if (!want.isUniform()) ASSERT_LT(degreesBetween(glm::dvec3(got.normal), glm::dvec3(want.normal)), 0.8);
                    EXPECT_LE(rec.minValue, got.front);
                    EXPECT_GE(rec.maxValue, got.front);
                }
        if (rec.parent != core::hvo::kNoNode) {
            EXPECT_LE(reader->nodes()[rec.parent].minValue, rec.minValue);
            EXPECT_GE(reader->nodes()[rec.parent].maxValue, rec.maxValue);
        }
    }
    EXPECT_EQ(reader->nodes()[0].minValue, 1.0f);
    EXPECT_EQ(reader->nodes()[0].maxValue, 3.0f);

    // Where voxels are expected, a sentence instead of cells read as samples.
    try {
        core::OctreeReader::open(dir.file("s.hvo"));
        ADD_FAILURE() << "a split-voxel octree was opened as voxels";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("a split-voxel octree"), std::string::npos) << e.what();
    }
    // A newer version, and a version 1 header marked split (checksums made right, so that the
    // version is what is refused).
    const auto rewritten = [&](std::uint32_t version, std::uint32_t flags) {
        std::fstream f(dir.file("s.hvo"), std::ios::in | std::ios::out | std::ios::binary);
        core::hvo::FileHeader h;
        f.read(reinterpret_cast<char*>(&h), sizeof h);
        h.version = version;
        h.flags = flags;
        h.headerChecksum = core::BrickCodec::checksum(&h, offsetof(core::hvo::FileHeader, headerChecksum));
        f.seekp(0);
        f.write(reinterpret_cast<const char*>(&h), sizeof h);
    };
    const auto flags = reader->header().flags;
    rewritten(3, flags);
    try {
        core::OctreeReader::open(dir.file("s.hvo"), true);
        ADD_FAILURE() << "version 3 was read";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("format version 3, written by a newer Holovox"), std::string::npos) << e.what();
    }
    rewritten(1, flags);
    EXPECT_THROW(core::OctreeReader::open(dir.file("s.hvo"), true), core::Error);
    rewritten(2, flags);
    EXPECT_NO_THROW(core::OctreeReader::open(dir.file("s.hvo"), true));
}

namespace {
/// A source that records the slabs asked of it (the builder streams: increasing slices per pass).
class RecordingSource final : public core::VoxelSource {
public:
    explicit RecordingSource(core::VoxelSource& inner) : inner_(inner) {}
    const core::VolumeGeometry& geometry() const override { return inner_.geometry(); }
    void readSlices(std::uint32_t first, std::uint32_t count, void* dst) override {
        reads.push_back({first, count});
        inner_.readSlices(first, count, dst);
    }
    std::string describe() const override { return inner_.describe(); }
    std::vector<std::array<std::uint32_t, 2>> reads;

private:
    core::VoxelSource& inner_;
};
}  // namespace

// The streamed build (rows of cells along z, bricks written as their rows complete) gives every
// level exactly as SplitVoxelGrid fits it with the whole volume in memory: the CT phantom's
// intensities (threshold found in a first pass) and a label map, with several cell sizes,
// overlaps and brick sizes (many brick rows per level). The volume is read in increasing
// slabs, once per pass.
TEST(SplitVoxelOctree, AStreamedBuildEqualsTheLevelsHeldWhole) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({70, 58, 53});
    for (const auto& [n, m, brick, labels] : {std::tuple{2u, 2u, 4u, false}, std::tuple{3u, 1u, 8u, false},
                                               std::tuple{2u, 0u, 4u, true}}) {
        test::DenseVolume dense;
        dense.dims = phantom.geometry().dims;
        for (std::uint32_t k = 0; k < 53; ++k)
            for (std::uint32_t j = 0; j < 58; ++j)
                for (std::uint32_t i = 0; i < 70; ++i) {
                    const double hu = phantom.voxel(i, j, k);
                    dense.values.push_back(labels ? (hu > 300 ? 2.0 : hu > -200 ? 1.0 : 0.0) : hu);
                }
        core::VolumeGeometry g = phantom.geometry();
        if (labels) {
            g.scalarType = core::ScalarType::UInt8;
            g.isLabel = true;
        }
        test::MemoryVoxelSource memory(g, dense);
        RecordingSource source(memory);
        core::BuildOptions b;
        b.brickSize = brick;
        core::SplitVoxelOptions o;
        o.n = n;
        o.overlap = m;
        o.labels = labels;
        core::JobContext job;
        core::SplitVoxelOctreeBuilder(b, o).build(source, dir.file("s.hvo"), job);
        // One pass for labels, two for intensities without a threshold, each in increasing slabs.
        int passes = 0;
        for (std::size_t r = 0; r < source.reads.size(); ++r) {
            if (source.reads[r][0] == 0) ++passes;
            else ASSERT_EQ(source.reads[r][0], source.reads[r - 1][0] + source.reads[r - 1][1]);
        }
        EXPECT_EQ(passes, labels ? 1 : 2);
        const auto reader = core::OctreeReader::open(dir.file("s.hvo"), true);
        std::vector<core::SplitVoxelGrid> levels{core::SplitVoxelGrid::build(memory, o, job)};
        while (int(levels.size()) < reader->levelCount()) levels.push_back(levels.back().coarser(o, job));
        ASSERT_GE(reader->levelCount(), 3);
        const std::size_t bytes = core::SplitVoxel::encodedSize(core::scalarSize(g.scalarType));
        std::vector<std::uint8_t> want(bytes);
        std::size_t cells = 0;
        for (std::uint32_t id = 0; id < reader->nodes().size(); ++id) {
            const auto& rec = reader->nodes()[id];
            const auto brickData = reader->readBrick(id);
            const auto* got = reinterpret_cast<const std::uint8_t*>(brickData.data.data());
            const auto& level = levels[rec.level];
            const auto& d = level.dims();
            for (std::uint32_t z = 0; z < brick; ++z)
                for (std::uint32_t y = 0; y < brick; ++y)
                    for (std::uint32_t x = 0; x < brick; ++x, got += bytes, ++cells) {
                        level.at(std::min(rec.x * brick + x, d[0] - 1), std::min(rec.y * brick + y, d[1] - 1),
                                 std::min(rec.z * brick + z, d[2] - 1))
                            .encode(want.data(), core::scalarSize(g.scalarType), g.scalarType == core::ScalarType::Int16);
                        ASSERT_EQ(std::memcmp(got, want.data(), bytes), 0)
                            << "N " << n << " M " << m << " node " << id << " level " << int(rec.level) << " cell " << x << "," << y << "," << z;
                    }
        }
        std::printf("N %u, M %u, bricks of %u%s: %d levels, %zu cells, all as held whole\n", n, m, brick,
                    labels ? ", labels" : "", reader->levelCount(), cells);
    }
}
