// MetaImage files, written here by hand: the plain ones streamed by Holovox as raw data (local
// and detached data, HeaderSize -1, big-endian), compressed ones inflated as they are read, and
// the broken ones refused with a sentence that names the file.

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include "core/base/Error.h"
#include "core/volume/MetaImageHeader.h"
#include "core/volume/VoxelSourceFactory.h"
#include "core/volume/VtkImageSource.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {
using test::errorOf;

std::vector<std::int16_t> ramp(std::size_t n) {
    std::vector<std::int16_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = std::int16_t(int(i % 4000) - 1024);
    return v;
}

std::string bytesOf(const std::vector<std::int16_t>& v, bool bigEndian = false) {
    std::string out(reinterpret_cast<const char*>(v.data()), v.size() * 2);
    if (bigEndian)
        for (std::size_t i = 0; i < out.size(); i += 2) std::swap(out[i], out[i + 1]);
    return out;
}


const char* kHead = "ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = 6 5 40\nElementType = MET_SHORT\n"
                    "ElementSpacing = 0.5 0.5 2\nOffset = -10 20 -30\n";
}  // namespace

TEST(MetaImage, LocalDataIsStreamedExactlyWithItsGeometry) {
    test::TempDir dir;
    const auto v = ramp(6 * 5 * 40);
    std::ofstream(dir.file("a.mha"), std::ios::binary)
        << kHead << "TransformMatrix = 0 1 0 -1 0 0 0 0 1\nBinaryDataByteOrderMSB = True\nElementDataFile = LOCAL\n"
        << bytesOf(v, true);
    const auto h = core::MetaImageHeader::read(dir.file("a.mha"));
    EXPECT_EQ(h.streamReason, "");
    auto src = core::VoxelSourceFactory::open(dir.file("a.mha"));
    const auto& g = src->geometry();
    EXPECT_EQ(g.dims, (std::array<std::uint32_t, 3>{6, 5, 40}));
    EXPECT_EQ(g.spacing, glm::dvec3(0.5, 0.5, 2));
    EXPECT_EQ(g.origin, glm::dvec3(-10, 20, -30));
    EXPECT_EQ(g.direction[0], glm::dvec3(0, 1, 0));  // row 0 of TransformMatrix: axis i's direction
    EXPECT_EQ(g.direction[1], glm::dvec3(-1, 0, 0));
    EXPECT_EQ(test::readAll<std::int16_t>(*src), v);
}

TEST(MetaImage, DetachedDataWithHeaderSizeMinusOneSkipsItsPreamble) {
    test::TempDir dir;
    const auto v = ramp(6 * 5 * 40);
    std::ofstream(dir.file("b.mhd")) << kHead << "HeaderSize = -1\nElementDataFile = b.raw\n";
    std::ofstream(dir.file("b.raw"), std::ios::binary) << std::string(77, 'x') << bytesOf(v);
    auto src = core::VoxelSourceFactory::open(dir.file("b.mhd"));
    EXPECT_EQ(test::readAll<std::int16_t>(*src), v);
}

namespace {
std::string deflated(const std::string& raw) {
    std::vector<unsigned char> z(compressBound(uLong(raw.size())));
    uLongf size = uLongf(z.size());
    EXPECT_EQ(compress2(z.data(), &size, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 6), Z_OK);
    return std::string(reinterpret_cast<const char*>(z.data()), size);
}
}  // namespace

TEST(MetaImage, CompressedDataIsInflatedAsItIsRead) {
    test::TempDir dir;
    const auto v = ramp(6 * 5 * 40);
    const std::string z = deflated(bytesOf(v, true));
    std::ofstream(dir.file("c.mha"), std::ios::binary)
        << kHead << "BinaryDataByteOrderMSB = True\nCompressedData = True\nCompressedDataSize = " << z.size()
        << "\nElementDataFile = LOCAL\n" << z;
    EXPECT_EQ(core::MetaImageHeader::read(dir.file("c.mha")).streamReason, "");
    auto src = core::VoxelSourceFactory::open(dir.file("c.mha"));
    EXPECT_EQ(src->geometry().origin, glm::dvec3(-10, 20, -30));
    EXPECT_EQ(test::readAll<std::int16_t>(*src), v);
    // Slabs forwards, then one before them (the stream starts again).
    const std::size_t slice = 6 * 5;
    std::vector<std::int16_t> slab(slice * 3);
    for (std::uint32_t first : {5u, 20u, 37u, 2u}) {
        src->readSlices(first, 3, slab.data());
        for (std::size_t i = 0; i < slab.size(); ++i) ASSERT_EQ(slab[i], v[first * slice + i]) << "slab at " << first;
    }
}

TEST(MetaImage, CompressedDataCutShortOrCorruptIsRefused) {
    test::TempDir dir;
    const auto v = ramp(6 * 5 * 40);
    const std::string z = deflated(bytesOf(v));
    auto write = [&](const std::string& name, const std::string& extra, const std::string& data) {
        std::ofstream(dir.file(name), std::ios::binary)
            << kHead << "CompressedData = True\n" << extra << "ElementDataFile = LOCAL\n" << data;
        return errorOf([&] {
            auto src = core::VoxelSourceFactory::open(dir.file(name));
            test::readAll<std::int16_t>(*src);
        });
    };
    // Shorter than its CompressedDataSize: refused before any voxel is read.
    std::string e = write("short.mha", "CompressedDataSize = " + std::to_string(z.size()) + "\n", z.substr(0, z.size() / 2));
    EXPECT_NE(e.find(dir.file("short.mha") + ": truncated"), std::string::npos) << e;
    // No size given and cut short: the stream runs out at a slice.
    e = write("cut.mha", "", z.substr(0, z.size() / 2));
    EXPECT_NE(e.find(dir.file("cut.mha") + ": its compressed data ends at slice"), std::string::npos) << e;
    // Bytes changed in the middle of the stream.
    std::string bad = z;
    for (std::size_t i = bad.size() / 3; i < bad.size() / 3 + 40; ++i) bad[i] = char(bad[i] ^ 0x5a);
    e = write("bad.mha", "", bad);
    EXPECT_NE(e.find(dir.file("bad.mha") + ": its compressed data"), std::string::npos) << e;
    // A stream of more voxels than DimSize: not a plausible volume of the wrong size.
    e = write("many.mha", "", deflated(bytesOf(v) + std::string(1000, '\0')));
    EXPECT_NE(e.find("more voxels than its header describes"), std::string::npos) << e;
    // A stream of fewer voxels than DimSize.
    e = write("few.mha", "", deflated(bytesOf(v).substr(0, 1000)));
    EXPECT_NE(e.find("fewer voxels than its header describes"), std::string::npos) << e;
}

TEST(MetaImage, BrokenHeadersAndDataAreRefusedNamingTheFile) {
    test::TempDir dir;
    const auto v = ramp(6 * 5 * 40);
    struct Case {
        std::string name, text, expect;
    };
    const std::vector<Case> cases = {
        {"short.mha", std::string(kHead) + "ElementDataFile = LOCAL\n" + bytesOf(v).substr(0, 1000), "bytes but the file has"},
        {"dims.mha", "ObjectType = Image\nNDims = 3\nDimSize = 6 5\nElementType = MET_SHORT\nElementDataFile = LOCAL\n",
         "DimSize"},
        {"zero.mha", "ObjectType = Image\nNDims = 3\nDimSize = 6 0 4\nElementType = MET_SHORT\nElementDataFile = LOCAL\n",
         "DimSize"},
        {"nodims.mha", "ObjectType = Image\nNDims = 3\nElementType = MET_SHORT\nElementDataFile = LOCAL\n", "no DimSize"},
        {"matrix.mha", std::string(kHead) + "TransformMatrix = 1 0 0 1 0 0 0 0 1\nElementDataFile = LOCAL\n" + bytesOf(v),
         "dependent directions"},
        {"mesh.mha", "ObjectType = Mesh\nNDims = 3\nElementDataFile = LOCAL\n", "not an image"},
        {"time.mha",  // a 4-D image: its 16-number TransformMatrix had been read as a 3 x 3 one
         "ObjectType = Image\nNDims = 4\nDimSize = 6 5 4 2\nTransformMatrix = 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
         "ElementType = MET_SHORT\nElementDataFile = LOCAL\n",
         "NDims = 4 (a time series or vectors): Holovox reads 3-D MetaImages only"},
        {"nodata.mha", std::string(kHead), "no ElementDataFile"},
        {"missing.mhd", std::string(kHead) + "ElementDataFile = gone.raw\n", "gone.raw"},
        {"rgb.mha", std::string(kHead) + "ElementNumberOfChannels = 3\nElementDataFile = LOCAL\n" + bytesOf(v) + bytesOf(v) + bytesOf(v),
         "its voxels hold 3 values each (ElementNumberOfChannels), as a colour or vector image does"},
    };
    for (const auto& c : cases) {
        std::ofstream(dir.file(c.name), std::ios::binary) << c.text;
        const std::string e = errorOf([&] {
            auto src = core::VoxelSourceFactory::open(dir.file(c.name));
            test::readAll<std::int16_t>(*src);
        });
        EXPECT_NE(e.find(c.expect), std::string::npos) << c.name << ": " << e;
        EXPECT_NE(e.find(c.name == "missing.mhd" ? "gone.raw" : c.name), std::string::npos) << c.name << ": " << e;
    }
}

TEST(MetaImage, AnOrientationOtherThanItksIsReported) {
    test::TempDir dir;
    const auto v = ramp(6 * 5 * 40);
    std::ofstream(dir.file("o.mha"), std::ios::binary)
        << kHead << "AnatomicalOrientation = LPI\nElementDataFile = LOCAL\n" << bytesOf(v);
    auto src = core::VoxelSourceFactory::open(dir.file("o.mha"));
    ASSERT_EQ(src->warnings().size(), 1u);
    EXPECT_NE(src->warnings()[0].find("AnatomicalOrientation is LPI"), std::string::npos);
}

// A volume kept as a file per slice (ElementDataFile = LIST, or a file pattern) is streamed slice
// by slice, with the voxels, order and geometry VTK's own MetaIO reader gives the same files
// (VtkImageSource, which had read such a list whole). Missing and short files, a list that does
// not match DimSize, and a pattern that is not a plain integer (a "%s" or "%n" handed to a printf)
// are refused naming what is wrong.
TEST(MetaImage, SliceListsAreStreamedAsVtkReadsThem) {
    test::TempDir dir;
    const auto v = ramp(6 * 5 * 40);
    std::string list;
    for (int k = 0; k < 40; ++k) {
        const std::vector<std::int16_t> slice(v.begin() + k * 30, v.begin() + (k + 1) * 30);
        std::ofstream(dir.file("s" + std::to_string(k) + ".raw"), std::ios::binary) << bytesOf(slice, true);
        std::ofstream(dir.file("p" + std::string(1 + 2 * k < 10 ? "0" : "") + std::to_string(1 + 2 * k) + ".raw"), std::ios::binary)
            << bytesOf(slice, true);
        list += "s" + std::to_string(k) + ".raw\n";
    }
    const std::string head = std::string(kHead) + "TransformMatrix = 0 1 0 -1 0 0 0 0 1\nBinaryDataByteOrderMSB = True\n";
    std::ofstream(dir.file("list.mhd")) << head << "ElementDataFile = LIST 2D\n" << list;
    std::ofstream(dir.file("pattern.mhd")) << head << "ElementDataFile = p%02d.raw 1 79 2\n";
    // MetaIO's short forms: files 1 to DimSize's third, or from a first number on; and a name
    // with spaces, rejoined from all but the last three words.
    for (int k = 0; k < 40; ++k) {
        std::filesystem::copy_file(dir.file("s" + std::to_string(k) + ".raw"), dir.file("q" + std::to_string(k + 1) + ".raw"));
        std::filesystem::copy_file(dir.file("s" + std::to_string(k) + ".raw"), dir.file("my scan" + std::to_string(k + 5) + ".raw"));
    }
    std::ofstream(dir.file("short.mhd")) << head << "ElementDataFile = q%d.raw\n";
    std::ofstream(dir.file("from.mhd")) << head << "ElementDataFile = s%d.raw 0\n";
    std::ofstream(dir.file("spaces.mhd")) << head << "ElementDataFile = my scan%d.raw 5 44 1\n";
    for (const char* name : {"list.mhd", "pattern.mhd", "short.mhd", "from.mhd", "spaces.mhd"}) {
        EXPECT_EQ(core::MetaImageHeader::read(dir.file(name)).streamReason, "") << name;
        auto src = core::VoxelSourceFactory::open(dir.file(name));
        EXPECT_EQ(src->geometry().dims, (std::array<std::uint32_t, 3>{6, 5, 40}));
        EXPECT_EQ(src->geometry().spacing, glm::dvec3(0.5, 0.5, 2));
        EXPECT_EQ(src->geometry().direction[1], glm::dvec3(-1, 0, 0));
        EXPECT_EQ(test::readAll<std::int16_t>(*src), v) << name;
    }
    core::VtkImageSource vtk(dir.file("list.mhd"));  // VTK's MetaIO, reading the list whole
    EXPECT_EQ(vtk.geometry().dims, (std::array<std::uint32_t, 3>{6, 5, 40}));
    EXPECT_EQ(vtk.geometry().origin, glm::dvec3(-10, 20, -30));
    EXPECT_EQ(test::readAll<std::int16_t>(vtk), v);

    auto refusal = [&](const std::string& dataFile, const std::string& body = {}) {
        std::ofstream(dir.file("bad.mhd")) << head << "ElementDataFile = " << dataFile << "\n" << body;
        return errorOf([&] { core::VoxelSourceFactory::open(dir.file("bad.mhd")); });
    };
    std::filesystem::resize_file(dir.file("s7.raw"), 59);
    EXPECT_NE(refusal("LIST", list).find("slice 7's file " + dir.file("s7.raw") + " holds 59 bytes, not the 60 of one slice"),
              std::string::npos);
    std::filesystem::remove(dir.file("s7.raw"));
    EXPECT_NE(refusal("LIST", list).find("slice 7's file " + dir.file("s7.raw") + " cannot be read"), std::string::npos);
    EXPECT_NE(refusal("LIST", "s0.raw\ns1.raw\n").find("names 2 slice files for DimSize's 40 slices"), std::string::npos);
    EXPECT_NE(refusal("LIST").find("LIST names no file"), std::string::npos);
    for (const char* hostile : {"p%s.raw 1 40 1", "p%n%d.raw 1 40 1", "p%d%d.raw 1 40 1", "p%999999d.raw 1 40 1"})
        EXPECT_NE(refusal(hostile).find("is not a name with one integer"), std::string::npos) << hostile;
    for (const char* wrongWay : {"p%02d.raw 1 79 0", "s%d.raw 3 2 5"})
        EXPECT_NE(refusal(wrongWay).find("run the wrong way for its step"), std::string::npos) << wrongWay;
    for (const char* down : {"p%02d.raw 79 1 -2", "s%d.raw 0 1 -5"})
        EXPECT_NE(refusal(down).find("counts down"), std::string::npos) << down;
    for (const char* outOfRange : {"p%d.raw 1 9000000000000000000 1", "m%d.raw -9223372036854775808 0 -1", "s%d.raw 0 2 x"})
        EXPECT_NE(refusal(outOfRange).find("where a file number should be"), std::string::npos) << outOfRange;
    EXPECT_NE(refusal("i%.raw 0 2 1").find("is not a name with one integer"), std::string::npos);
    EXPECT_NE(refusal("i.raw 0 2 1 2 %").find("where a file number should be"), std::string::npos);
    EXPECT_NE(refusal("s%d.raw 1 40").find("is not a file pattern, or one with first, last and step"), std::string::npos);
    EXPECT_NE(refusal("LIST 3D", list).find("Holovox reads a list of 2-D slice files only"), std::string::npos);
}
