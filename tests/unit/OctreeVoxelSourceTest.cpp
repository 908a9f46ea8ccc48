// An octree read back as a volume (core::OctreeVoxelSource): the CT phantom on a grid that is
// no multiple of the brick size comes back voxel for voxel, whatever the slab sizes; a
// split-voxel octree built from the octree equals the one built from the phantom, cell for cell;
// lossy, split-voxel and corrupt octrees are refused in a sentence naming the file.
#include <gtest/gtest.h>

#include <fstream>

#include "core/base/JobContext.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeVoxelSource.h"
#include "core/octree/SplitVoxelOctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
std::shared_ptr<const core::OctreeReader> built(core::VoxelSource& source, const std::string& path, core::BuildOptions b) {
    core::JobContext job;
    core::OctreeBuilder(b).build(source, path, job);
    return core::OctreeReader::open(path);
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const core::Error& e) {
        return e.what();
    }
    return "(no error)";
}
}  // namespace

TEST(OctreeVoxelSource, GivesBackEveryVoxelOfTheVolume) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({70, 45, 37});
    core::BuildOptions b;
    b.brickSize = 16;
    auto reader = built(phantom, dir.file("p.hvo"), b);
    core::OctreeVoxelSource source(reader);
    EXPECT_EQ(source.geometry().dims, phantom.geometry().dims);
    EXPECT_EQ(source.geometry().spacing, phantom.geometry().spacing);
    EXPECT_TRUE(source.warnings().empty());
    const std::size_t slice = 70 * 45;
    std::vector<std::int16_t> got(slice * 37);
    for (std::uint32_t k = 0; k < 37;) {  // slabs of 1 to 7 slices, across brick rows
        const std::uint32_t n = std::min<std::uint32_t>(1 + k % 7, 37 - k);
        source.readSlices(k, n, got.data() + slice * k);
        k += n;
    }
    std::size_t wrong = 0;
    for (std::uint32_t k = 0; k < 37; ++k)
        for (std::uint32_t j = 0; j < 45; ++j)
            for (std::uint32_t i = 0; i < 70; ++i) wrong += got[(k * 45 + j) * 70 + i] != phantom.voxel(i, j, k);
    EXPECT_EQ(wrong, 0u);
    EXPECT_NE(errorOf([&] { source.readSlices(30, 8, got.data()); }).find("outside"), std::string::npos);
}

TEST(OctreeVoxelSource, ASplitVoxelOctreeBuiltFromItEqualsOneBuiltFromTheVolume) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({48, 40, 36});
    core::BuildOptions b;
    b.brickSize = 16;
    auto reader = built(phantom, dir.file("p.hvo"), b);
    core::OctreeVoxelSource source(reader);
    core::JobContext job;
    core::SplitVoxelOptions o;
    core::SplitVoxelOctreeBuilder(b, o).build(phantom, dir.file("a.hvo"), job);
    core::SplitVoxelOctreeBuilder(b, o).build(source, dir.file("b.hvo"), job);
    const auto a = core::OctreeReader::open(dir.file("a.hvo"), true), c = core::OctreeReader::open(dir.file("b.hvo"), true);
    ASSERT_EQ(a->nodes().size(), c->nodes().size());
    for (std::uint32_t n = 0; n < a->nodes().size(); ++n)
        ASSERT_EQ(a->readBrick(n).data, c->readBrick(n).data) << "node " << n;
}

TEST(OctreeVoxelSource, WhatIsNotTheVolumesOwnValuesIsRefusedInWords) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({32, 32, 32});
    core::BuildOptions lossy;
    lossy.lossy8 = true;
    auto reader = built(phantom, dir.file("lossy.hvo"), lossy);
    EXPECT_NE(errorOf([&] { core::OctreeVoxelSource{reader}; }).find("lossily"), std::string::npos);
    core::JobContext job;
    core::SplitVoxelOctreeBuilder(core::BuildOptions{}, core::SplitVoxelOptions{}).build(phantom, dir.file("s.hvo"), job);
    std::shared_ptr<const core::OctreeReader> split = core::OctreeReader::open(dir.file("s.hvo"), true);
    EXPECT_NE(errorOf([&] { core::OctreeVoxelSource{split}; }).find("split-voxel octree"), std::string::npos);
    // An empty threshold is said, not silently applied.
    core::BuildOptions empty;
    empty.emptyBelow = -500.0;
    auto thresholded = built(phantom, dir.file("e.hvo"), empty);
    const auto warnings = core::OctreeVoxelSource(thresholded).warnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("empty threshold"), std::string::npos);
    // A brick damaged on disk: the read names the file.
    auto plain = built(phantom, dir.file("p.hvo"), core::BuildOptions{});
    const auto& n = plain->nodes().front();
    {
        std::fstream f(dir.file("p.hvo"), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(n.payloadOffset + n.payloadSize / 2));
        f.put('\x5a').put('\x5a').put('\x5a');
    }
    core::OctreeVoxelSource damaged(core::OctreeReader::open(dir.file("p.hvo")));
    std::vector<std::int16_t> buf(32 * 32 * 32);
    EXPECT_NE(errorOf([&] { damaged.readSlices(0, 32, buf.data()); }).find("p.hvo"), std::string::npos);
}
