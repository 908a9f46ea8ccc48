// NRRD with gzip encoding (3D Slicer's default when it saves a volume), written here by hand
// with zlib's gzip writer: inflated as it is read, in the same place as its raw twin, and
// refused with a sentence when cut short.

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
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
    EXPECT_NE(b.find("NRRD encoding 'bzip2' is not supported (raw and gzip are)"), std::string::npos) << b;
}
