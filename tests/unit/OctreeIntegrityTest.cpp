#include <gtest/gtest.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <functional>

#include "core/octree/BrickCodec.h"
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

namespace {
/// Rewrites the header through `edit` and gives it a valid checksum again: a forged file.
void forgeHeader(const std::string& from, const std::string& to, const std::function<void(core::hvo::FileHeader&)>& edit) {
    std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing);
    core::hvo::FileHeader h{};
    {
        std::ifstream in(to, std::ios::binary);
        in.read(reinterpret_cast<char*>(&h), sizeof h);
    }
    edit(h);
    h.headerChecksum = core::BrickCodec::checksum(&h, offsetof(core::hvo::FileHeader, headerChecksum));
    std::fstream f(to, std::ios::in | std::ios::out | std::ios::binary);
    f.write(reinterpret_cast<const char*>(&h), sizeof h);
}

void forgeNode(const std::string& from, const std::string& to, const std::function<void(core::hvo::NodeRecord&)>& edit) {
    std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing);
    core::hvo::FileHeader h{};
    std::vector<core::hvo::NodeRecord> nodes;
    {
        std::ifstream in(to, std::ios::binary);
        in.read(reinterpret_cast<char*>(&h), sizeof h);
        nodes.resize(h.nodeCount);
        in.seekg(std::streamoff(h.nodeTableOffset));
        in.read(reinterpret_cast<char*>(nodes.data()), std::streamsize(nodes.size() * sizeof nodes[0]));
    }
    for (auto& n : nodes)
        if (n.payloadSize > 0) {
            edit(n);
            break;
        }
    h.nodeTableChecksum = core::BrickCodec::checksum(nodes.data(), nodes.size() * sizeof nodes[0]);
    h.headerChecksum = core::BrickCodec::checksum(&h, offsetof(core::hvo::FileHeader, headerChecksum));
    std::fstream f(to, std::ios::in | std::ios::out | std::ios::binary);
    f.write(reinterpret_cast<const char*>(&h), sizeof h);
    f.seekp(std::streamoff(h.nodeTableOffset));
    f.write(reinterpret_cast<const char*>(nodes.data()), std::streamsize(nodes.size() * sizeof nodes[0]));
}
}  // namespace

// Headers and node tables with valid checksums but hostile fields: each refused with a sentence,
// at once, without allocating from what the file claims.
TEST(OctreeIntegrity, ForgedFilesWithValidChecksumsAreRefused) {
    test::TempDir dir;
    const auto path = buildPhantom(dir);
    ASSERT_EQ(openError(path), "");
    const auto forged = dir.file("forged.hvo");
    struct Case {
        const char* what;
        std::function<void(core::hvo::FileHeader&)> edit;
        const char* expect;
    };
    const Case cases[] = {
        {"huge dimensions in bricks of 1",
         [](auto& h) { h.dims[0] = h.dims[1] = h.dims[2] = 65535; h.brickSize = 1; }, "does not match the volume dimensions"},
        {"dimensions needing more bricks than the table has", [](auto& h) { h.dims[2] = 600; }, "does not match the volume dimensions"},
        {"a dimension past what Holovox reads", [](auto& h) { h.dims[2] = 4000000; }, "is too large"},
        {"a node table offset that wraps around",
         [](auto& h) { h.nodeTableOffset = ~std::uint64_t(0) - 100; }, "node table out of bounds"},
        {"a node count that overflows the table's size",
         [](auto& h) { h.nodeCount = (std::uint64_t(1) << 58) + h.nodeCount; }, "node table out of bounds"},
        {"brick size 0", [](auto& h) { h.brickSize = 0; }, "brick size or border out of range"},
        {"zero spacing", [](auto& h) { h.spacing[1] = 0.0; }, "not a valid .hvo file"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.what);
        forgeHeader(path, forged, c.edit);
        const auto start = std::chrono::steady_clock::now();
        const std::string e = openError(forged);
        EXPECT_NE(e.find(c.expect), std::string::npos) << e;
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
    }
    forgeNode(path, forged, [](auto& n) { n.payloadOffset = ~std::uint64_t(0) - 10; });
    EXPECT_NE(openError(forged).find("is out of bounds"), std::string::npos) << openError(forged);
    forgeNode(path, forged, [](auto& n) { n.payloadSize = 0xffffffffu; });
    EXPECT_NE(openError(forged).find("is out of bounds"), std::string::npos) << openError(forged);
}
