// NRRD with gzip encoding (3D Slicer's default when it saves a volume), written here by hand
// with zlib's gzip writer: inflated as it is read, in the same place as its raw twin, and
// refused with a sentence when cut short.

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "core/volume/VoxelSourceFactory.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {
const char* kHeader = "NRRD0004\ntype: short\ndimension: 3\nspace: right-anterior-superior\nsizes: 7 6 33\n"
                      "space directions: (0,-0.8,0) (0.9,0,0) (0,0,2.5)\nkinds: domain domain domain\n"
                      "endian: little\nspace origin: (12,-30,40)\n";

std::vector<std::int16_t> values() {
    std::vector<std::int16_t> v(7 * 6 * 33);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::int16_t(int(i * 13 % 3000) - 1000);
    return v;
}

/// Writes `data` gzip-compressed to `path` (appending after what is there).
void appendGzip(const std::string& path, const std::string& data) {
    gzFile f = gzopen(path.c_str(), "ab");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(gzwrite(f, data.data(), unsigned(data.size())), int(data.size()));
    gzclose(f);
}
}  // namespace

TEST(NrrdGzip, AttachedAndDetachedDataEqualTheRawFile) {
    test::TempDir dir;
    const auto v = values();
    const std::string bytes(reinterpret_cast<const char*>(v.data()), v.size() * 2);
    std::ofstream(dir.file("raw.nrrd"), std::ios::binary) << kHeader << "encoding: raw\n\n" << bytes;
    std::ofstream(dir.file("gz.nrrd"), std::ios::binary) << kHeader << "encoding: gzip\n\n";
    appendGzip(dir.file("gz.nrrd"), bytes);
    std::ofstream(dir.file("d.nhdr")) << kHeader << "encoding: gz\ndata file: d.raw.gz\n\n";
    appendGzip(dir.file("d.raw.gz"), bytes);
    auto raw = core::VoxelSourceFactory::open(dir.file("raw.nrrd"));
    for (const char* name : {"gz.nrrd", "d.nhdr"}) {
        auto gz = core::VoxelSourceFactory::open(dir.file(name));
        EXPECT_EQ(gz->geometry().origin, raw->geometry().origin) << name;
        EXPECT_EQ(gz->geometry().direction, raw->geometry().direction) << name;
        EXPECT_EQ(gz->geometry().spacing, raw->geometry().spacing) << name;
        EXPECT_EQ(test::readAll<std::int16_t>(*gz), v) << name;
    }
}

TEST(NrrdGzip, CutShortIsAnErrorAtItsSlice) {
    test::TempDir dir;
    const auto v = values();
    const std::string bytes(reinterpret_cast<const char*>(v.data()), v.size() * 2);
    std::ofstream(dir.file("whole.nrrd"), std::ios::binary) << kHeader << "encoding: gzip\n\n";
    appendGzip(dir.file("whole.nrrd"), bytes);
    std::ifstream in(dir.file("whole.nrrd"), std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir.file("cut.nrrd"), std::ios::binary) << all.substr(0, all.size() * 2 / 3);
    const std::string e = test::errorOf([&] {
        auto src = core::VoxelSourceFactory::open(dir.file("cut.nrrd"));
        test::readAll<std::int16_t>(*src);
    });
    EXPECT_NE(e.find(dir.file("cut.nrrd") + ": its compressed data ends at slice"), std::string::npos) << e;
    std::ofstream(dir.file("bz.nrrd"), std::ios::binary) << kHeader << "encoding: bzip2\n\n" << "BZh";
    const std::string b = test::errorOf([&] { core::VoxelSourceFactory::open(dir.file("bz.nrrd")); });
    EXPECT_NE(b.find("NRRD encoding 'bzip2' is not supported (raw, gzip and ascii are)"), std::string::npos) << b;
}

// Deflate packs at most 1032 bytes into one: a header that promises more voxels than its
// compressed data can hold is refused when opened (a NRRD of 100000 x 100000 x 1000 over four
// gzipped values had taken 18 GB of memory and 57 s before bad_alloc), while data compressed as
// far as deflate goes (zeros, at its best level) still opens.
TEST(NrrdGzip, AHeaderPromisingMoreThanDeflateCanHoldIsRefusedWhenOpened) {
    test::TempDir dir;
    const std::string head = "NRRD0004\ntype: short\ndimension: 3\nendian: little\nencoding: gzip\n";
    std::ofstream(dir.file("big.nrrd"), std::ios::binary) << head << "sizes: 100000 100000 1000\n\n";
    appendGzip(dir.file("big.nrrd"), std::string(8, '\1'));
    const std::string e = test::errorOf([&] { core::VoxelSourceFactory::open(dir.file("big.nrrd")); });
    EXPECT_EQ(e.rfind(dir.file("big.nrrd") + ": its header needs 20000000000000 bytes once inflated, more than its ", 0), 0u) << e;
    EXPECT_NE(e.find(" bytes of compressed data can hold (deflate packs at most 1032 bytes into one)"), std::string::npos) << e;

    const std::string zeros(std::size_t(256) * 256 * 64 * 2, '\0');
    std::ofstream(dir.file("zeros.nrrd"), std::ios::binary) << head << "sizes: 256 256 64\n\n";
    gzFile f = gzopen(dir.file("zeros.nrrd").c_str(), "ab9");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(gzwrite(f, zeros.data(), unsigned(zeros.size())), int(zeros.size()));
    gzclose(f);
    const auto compressed = std::filesystem::file_size(dir.file("zeros.nrrd")) - head.size() - 19;
    EXPECT_GT(double(zeros.size()) / double(compressed), 1000.0);  // as far as deflate goes
    auto src = core::VoxelSourceFactory::open(dir.file("zeros.nrrd"));
    EXPECT_EQ(test::readAll<std::int16_t>(*src), std::vector<std::int16_t>(zeros.size() / 2, 0));
}
