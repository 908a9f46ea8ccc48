#include <gtest/gtest.h>

#include <fstream>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
std::string buildPhantom(const test::TempDir& dir, std::array<std::uint32_t, 3> dims = {40, 40, 40}) {
    core::PhantomVoxelSource p(dims, 3);
    core::BuildOptions opt;
    opt.brickSize = 16;
    core::JobContext job;
    core::OctreeBuilder(opt).build(p, dir.file("p.hvo"), job);
    return dir.file("p.hvo");
}

void patchByte(const std::string& path, std::uint64_t offset, unsigned char x) {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(std::streamoff(offset));
    char c;
    f.get(c);
    f.seekp(std::streamoff(offset));
    f.put(char(c ^ x));
}

std::string openError(const std::string& path) {
    try {
        core::OctreeReader::open(path);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(OctreeIntegrity, FlippedPayloadByteIsCaughtAndNamesTheNode) {
    test::TempDir dir;
    const auto path = buildPhantom(dir);
    std::uint32_t victim = 0;
    std::uint64_t offset = 0;
    {
        const auto r = core::OctreeReader::open(path);
        for (std::uint32_t i = 0; i < r->nodes().size(); ++i)
            if (r->nodes()[i].payloadSize > 100) victim = i;
        offset = r->nodes()[victim].payloadOffset + r->nodes()[victim].payloadSize / 2;
    }
    patchByte(path, offset, 0x10);
    const auto r = core::OctreeReader::open(path);  // the table is intact, so the file opens
    try {
        r->readBrick(victim);
        FAIL() << "corrupt brick was returned";
    } catch (const core::CorruptBrickError& e) {
        EXPECT_EQ(e.node(), victim);
        EXPECT_NE(std::string(e.what()).find("node " + std::to_string(victim)), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
    }
    // Every other brick still reads.
    for (std::uint32_t i = 0; i < r->nodes().size(); ++i)
        if (i != victim) EXPECT_NO_THROW(r->readBrick(i));
}

TEST(OctreeIntegrity, DamagedNodeTableOrHeaderIsRefusedWithAReason) {
    test::TempDir dir;
    const auto path = buildPhantom(dir);
    std::uint64_t table = 0;
    {
        const auto r = core::OctreeReader::open(path);
        table = r->header().nodeTableOffset;
    }
    patchByte(path, table + 70, 0x01);
    EXPECT_NE(openError(path).find("node table checksum"), std::string::npos) << openError(path);
    patchByte(path, table + 70, 0x01);  // restore
    EXPECT_EQ(openError(path), "");
    patchByte(path, 20, 0x01);  // dims in the header
    EXPECT_NE(openError(path).find("header checksum"), std::string::npos) << openError(path);
}

TEST(OctreeIntegrity, TruncatedFileAndForeignFilesAreRefused) {
    test::TempDir dir;
    const auto path = buildPhantom(dir);
    const auto size = std::filesystem::file_size(path);
    std::filesystem::resize_file(path, size - 10);
    const std::string e = openError(path);
    EXPECT_NE(e.find(path), std::string::npos) << e;
    EXPECT_NE(e.find("truncated"), std::string::npos) << e;
    std::ofstream(dir.file("text.hvo")) << "hello, this is not an octree";
    EXPECT_NE(openError(dir.file("text.hvo")).find("shorter than the header"), std::string::npos);
    std::ofstream(dir.file("zeros.hvo")) << std::string(4096, '\0');
    EXPECT_NE(openError(dir.file("zeros.hvo")).find("magic"), std::string::npos);
    EXPECT_NE(openError(dir.file("missing.hvo")).find("cannot open"), std::string::npos);
}

TEST(OctreeIntegrity, CancelledBuildLeavesNoFileBehind) {
    test::TempDir dir;
    core::PhantomVoxelSource p({64, 64, 256}, 3);
    core::BuildOptions opt;
    opt.brickSize = 16;
    core::JobContext* self = nullptr;
    core::JobContext job([&](const core::JobProgress& pr) {
        if (pr.fraction > 0.2) self->cancel();
    });
    self = &job;
    EXPECT_THROW(core::OctreeBuilder(opt).build(p, dir.file("p.hvo"), job), core::Cancelled);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(OctreeIntegrity, UnwritableOutputIsAnErrorNamingTheFile) {
    test::TempDir dir;
    core::PhantomVoxelSource p({8, 8, 8}, 3);
    core::JobContext job;
    const std::string out = dir.file("no/such/dir/p.hvo");
    try {
        core::OctreeBuilder(core::BuildOptions{}).build(p, out, job);
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find(out), std::string::npos) << e.what();
    }
    EXPECT_TRUE(dir.entries().empty());
}
