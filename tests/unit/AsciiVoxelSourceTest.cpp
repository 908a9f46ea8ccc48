// Volumes written as text (MetaImage with BinaryData = False, legacy VTK in ASCII), streamed by
// Holovox's AsciiVoxelSource: equal to VTK's own readers (which read the whole image) for every
// element type, in any slab order, and every hostile text refused with a sentence naming the
// file and the voxel, before anything is allocated for a header that promises more than its
// file holds.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "core/volume/VoxelSourceFactory.h"
#include "core/volume/VtkImageSource.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {
using test::errorOf;

// Value n of a test image of a type with the given range: spread over the whole range, both
// ends included, with fractions for floats.
double valueAt(std::size_t n, double lo, double hi, bool fractions) {
    if (n == 0) return lo;
    if (n == 1) return hi;
    const double t = double((n * 7919) % 1000) / 999.0;
    const double v = lo + t * (hi - lo);
    return fractions ? v : std::floor(v);
}

// The values as text with `digits` significant digits (0: whole numbers), laid out the untidy
// ways writers do: several to a line, tabs, CRLF.
std::string asText(const std::vector<double>& v, int digits) {
    std::string out;
    char number[64];
    for (std::size_t i = 0; i < v.size(); ++i) {
        std::snprintf(number, sizeof number, "%.*g", digits == 0 ? 20 : digits, v[i]);
        out += number;
        out += i % 7 == 6 ? "\r\n" : i % 5 == 4 ? "\t" : " ";
    }
    return out + "\n";
}

std::string metaImage(const std::string& dims, const char* type, const std::string& text, const std::string& extra = "") {
    return "ObjectType = Image\nNDims = 3\nDimSize = " + dims + "\nElementType = " + type +
           "\nElementSpacing = 0.5 0.75 2\nOffset = -10 20 -30\n" + extra + "BinaryData = False\nElementDataFile = LOCAL\n" + text;
}

std::string legacyVtk(const std::string& dims, std::size_t points, const char* type, const std::string& text) {
    return "# vtk DataFile Version 3.0\nascii test\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS " + dims +
           "\nSPACING 0.5 0.75 2\nORIGIN -10 20 -30\nPOINT_DATA " + std::to_string(points) + "\nSCALARS v " + type +
           "\nLOOKUP_TABLE default\n" + text;
}

void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// Reads slices 3-4, then 6-8 (skipping 5), then 0-1 (going back), 2 and 5, then any past 8
// in order: every voxel as a double.
std::vector<double> readOutOfOrder(core::VoxelSource& s) {
    const auto& d = s.geometry().dims;
    const std::size_t slice = std::size_t(d[0]) * d[1];
    std::vector<double> out(slice * d[2], -12345.0);
    core::dispatchScalar(s.geometry().scalarType, [&](auto tag) {
        using T = decltype(tag);
        std::vector<std::pair<std::uint32_t, std::uint32_t>> slabs{{3u, 2u}, {6u, 3u}, {0u, 2u}, {2u, 1u}, {5u, 1u}};
        if (d[2] > 9) slabs.push_back({9u, d[2] - 9});
        for (const auto& [first, count] : slabs) {
            std::vector<T> slab(slice * count);
            s.readSlices(first, count, slab.data());
            for (std::size_t i = 0; i < slab.size(); ++i) out[first * slice + i] = double(slab[i]);
        }
    });
    return out;
}
}  // namespace

TEST(AsciiVolumes, EveryTypeReadsAsVtksReadersReadTheWholeImage) {
    test::TempDir dir;
    struct Case {
        const char* meta;
        const char* vtk;
        double lo, hi;
        int digits;  // 0: whole numbers; 9: float values (each read back exactly); 17: doubles
        core::ScalarType stored;
    };
    const Case cases[] = {
        {"MET_UCHAR", "unsigned_char", 0, 255, 0, core::ScalarType::UInt8},
        {"MET_CHAR", "char", -128, 127, 0, core::ScalarType::Int16},
        {"MET_SHORT", "short", -32768, 32767, 0, core::ScalarType::Int16},
        {"MET_USHORT", "unsigned_short", 0, 65535, 0, core::ScalarType::UInt16},
        {"MET_INT", "int", -16777216, 16777216, 0, core::ScalarType::Float32},
        {"MET_FLOAT", "float", -3.5e4, 2.25e6, 9, core::ScalarType::Float32},
        {"MET_DOUBLE", "double", -1e-3, 1e30, 17, core::ScalarType::Float32},
    };
    const std::size_t n = 7 * 5 * 9;
    for (const Case& c : cases) {
        std::vector<double> v(n);
        for (std::size_t i = 0; i < n; ++i) {
            v[i] = valueAt(i, c.lo, c.hi, c.digits > 0);
            if (c.digits == 9) v[i] = double(float(v[i]));
        }
        const std::string text = asText(v, c.digits);
        write(dir.file("a.mha"), metaImage("7 5 9", c.meta, text));
        write(dir.file("a.vtk"), legacyVtk("7 5 9", n, c.vtk, text));
        for (const char* name : {"a.mha", "a.vtk"}) {
            SCOPED_TRACE(std::string(c.meta) + " in " + name);
            auto src = core::VoxelSourceFactory::open(dir.file(name));
            ASSERT_EQ(src->geometry().scalarType, c.stored);
            EXPECT_EQ(src->geometry().dims, (std::array<std::uint32_t, 3>{7, 5, 9}));
            EXPECT_EQ(src->geometry().spacing, glm::dvec3(0.5, 0.75, 2));
            EXPECT_EQ(src->geometry().origin, glm::dvec3(-10, 20, -30));
            const std::vector<double> got = readOutOfOrder(*src);
            if (c.stored != core::ScalarType::Float32 || std::string(c.meta) == "MET_INT")
                for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(got[i], v[i]) << "value " << i;
            if (std::string(c.meta) == "MET_INT") continue;  // VTK's readers refuse 32-bit integers
            core::VtkImageSource vtk(dir.file(name));  // the reference: VTK's reader, whole
            EXPECT_EQ(vtk.geometry().scalarType, c.stored);
            EXPECT_EQ(test::voxelValues(vtk), got);
        }
    }
}

// Text longer than one read (1 MiB and 256 bytes at a time): a token cut by the read's end is
// joined with its rest, wherever the cut falls; equal to VTK's reader, in and out of order.
TEST(AsciiVolumes, TokensCutByTheReadsEndAreJoined) {
    test::TempDir dir;
    const std::size_t n = 64 * 64 * 100;  // about 2.5 MiB of text
    std::vector<double> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = valueAt(i, -32768, 32767, false);
    const std::string text = asText(v, 0);
    ASSERT_GT(text.size(), std::size_t(2) << 20);
    const std::size_t chunk = (std::size_t(1) << 20) + 256;
    // Pad the text's start so that the first read ends 0, 1, 2 and 3 bytes into a token.
    std::size_t tokenAt = chunk - 1000;  // a token that begins a little before the first read's end
    while (tokenAt < text.size() && !(text[tokenAt - 1] == ' ' && text[tokenAt] == '-')) ++tokenAt;
    ASSERT_LT(tokenAt, chunk);
    for (const std::size_t into : {0u, 1u, 2u, 3u}) {
        SCOPED_TRACE("cut " + std::to_string(into) + " bytes into a token");
        const std::string padded = std::string(chunk - tokenAt - into, ' ') + text;  // the token at chunk - into
        write(dir.file("long.mha"), metaImage("64 64 100", "MET_SHORT", padded));
        auto src = core::VoxelSourceFactory::open(dir.file("long.mha"));
        EXPECT_EQ(readOutOfOrder(*src), v);
        core::VtkImageSource vtk(dir.file("long.mha"));
        EXPECT_EQ(test::voxelValues(vtk), v);
    }
}

TEST(AsciiVolumes, WholeNumbersWrittenAsFractionsOrWithASignAreRead) {
    test::TempDir dir;
    write(dir.file("w.mha"), metaImage("2 2 2", "MET_SHORT", "+5 3.0 1e2 -0 -32768 32767.000 7 -1.5e1\n"));
    auto src = core::VoxelSourceFactory::open(dir.file("w.mha"));
    EXPECT_EQ(test::readAll<std::int16_t>(*src), (std::vector<std::int16_t>{5, 3, 100, 0, -32768, 32767, 7, -15}));
    // Numbers too small for a float or a double are zero, as a C++ stream and teem read them.
    write(dir.file("tiny.mha"), metaImage("3 1 1", "MET_FLOAT", "1e-50 -1e-400 2.5\n"));
    EXPECT_EQ(test::readAll<float>(*core::VoxelSourceFactory::open(dir.file("tiny.mha"))), (std::vector<float>{0.0f, -0.0f, 2.5f}));
    write(dir.file("tiny64.mha"), metaImage("2 1 1", "MET_DOUBLE", "1e-400 7\n"));
    EXPECT_EQ(test::readAll<float>(*core::VoxelSourceFactory::open(dir.file("tiny64.mha"))), (std::vector<float>{0.0f, 7.0f}));
    // The ends of the 64-bit types, written out.
    write(dir.file("ends.mha"), metaImage("2 1 1", "MET_LONG_LONG", "-9223372036854775808 9223372036854775807\n"));
    EXPECT_EQ(test::readAll<float>(*core::VoxelSourceFactory::open(dir.file("ends.mha"))),
              (std::vector<float>{-9223372036854775808.0f, 9223372036854775807.0f}));
}

TEST(AsciiVolumes, HostileTextIsRefusedNamingTheFileAndTheVoxel) {
    test::TempDir dir;
    const std::string path = dir.file("h.mha");
    auto refusal = [&](const std::string& text) {
        write(path, text);
        const std::string e = errorOf([&] {
            auto src = core::VoxelSourceFactory::open(path);
            test::voxelValues(*src);
        });
        EXPECT_EQ(e.rfind(path + ": ", 0), 0u) << e;
        return e;
    };
    auto has = [](const std::string& e, const std::string& part) { return e.find(part) != std::string::npos; };
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_UCHAR", "10 20 30 40 50 60 70\n")),
                    "its text data end after 7 of the 8 voxel values its header gives"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_UCHAR", "1 2 3 4 5 6 7\n")),
                    "its text data are 14 bytes, too few for the 8 voxel values"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_UCHAR", "1 2 3 4 5 6 7 8 9\n")),
                    "its text data go on after the 8 voxel values its header gives ('9' follows)"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_UCHAR", "1 2 3 4 5 6 7 300\n")),
                    "its voxel (1, 1, 1) (value number 8), '300', is outside what its uint8 voxels hold (0 to 255)"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_CHAR", "-129 2 3 4 5 6 7 8\n")), "(-128 to 127)"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_USHORT", "1 2 -3 4 5 6 7 8\n")),
                    "its voxel (0, 1, 0) (value number 3), '-3', is outside what its uint16 voxels hold (0 to 65535)"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_SHORT", "1 2 3 4 5 6 7 x8\n")), "(value number 8), 'x8', is not a number"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_SHORT", "1 2 3 4 5 6 7 8,\n")), "'8,', is not a number"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_SHORT", "1 2 3.5 4 5 6 7 8\n")),
                    "'3.5', is not a whole number, as its int16 voxels are"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_SHORT", "1 2 3 nan 5 6 7 8\n")), "'nan', is not a number"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_SHORT", "1 2 3 1e400 5 6 7 8\n")), "is outside what its int16 voxels hold"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_SHORT", "1 2 3 " + std::string(300, '7') + " 5 6 7 8\n")),
                    "(value number 4) is more than 256 characters long, not a number"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_SHORT", "1 2 3 " + std::string(40, '7') + " 5 6 7 8\n")),
                    "'" + std::string(32, '7') + "...', is outside"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_FLOAT", "1 2 3 1e300 5 6 7 8\n")), "'1e300', is beyond what a 32-bit float holds"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_FLOAT", "1 2 3 -1e999 5 6 7 8\n")), "'-1e999', is beyond what a 32-bit float holds"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_DOUBLE", "1 2 3 1e999 5 6 7 8\n")), "'1e999', is beyond what a 64-bit float holds"));
    // Integers one past a 64-bit type's range, written out or with an exponent.
    EXPECT_TRUE(has(refusal(metaImage("2 1 1", "MET_LONG_LONG", "-9223372036854775809 0\n")),
                    "is outside what its int64 voxels hold (-9223372036854775808 to 9223372036854775807)"));
    EXPECT_TRUE(has(refusal(metaImage("2 1 1", "MET_ULONG_LONG", "18446744073709551616 0\n")), "is outside what its uint64 voxels hold"));
    EXPECT_TRUE(has(refusal(metaImage("2 1 1", "MET_LONG_LONG", "-9.223372036854775809e18 0\n")),
                    "is too large to be read exactly when written with a fraction or an exponent"));
    EXPECT_TRUE(has(refusal(metaImage("2 1 1", "MET_SHORT", "1e-400 0\n")), "is not a whole number"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_DOUBLE", "1 2 3 1e300 5 6 7 8\n")), "holds a value beyond what a 32-bit float can hold"));
    EXPECT_TRUE(has(refusal(metaImage("2 2 2", "MET_SHORT", std::string("1 2 3 4\0 5 6 7 8\n", 17))), "'4\\x00', is not a number"));
    // A header that promises more values than its file can hold is refused when opened: VTK's
    // reader had allocated 17 GiB for this one and failed after 76 s.
    write(path, metaImage("100000 100000 1000", "MET_SHORT", "1 2 3 4\n"));
    const auto start = std::chrono::steady_clock::now();
    const std::string e = errorOf([&] { core::VoxelSourceFactory::open(path); });
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
    EXPECT_TRUE(has(e, path + ": its text data are 8 bytes, too few for the 10000000000000 voxel values its header gives"))
        << e;
    // The same for legacy VTK files, which may go on with other attributes after the voxels.
    write(dir.file("h.vtk"), legacyVtk("2 2 2", 8, "short", "10 20 30 40 50 60 70\n"));
    EXPECT_TRUE(has(errorOf([&] { test::voxelValues(*core::VoxelSourceFactory::open(dir.file("h.vtk"))); }),
                    "its text data end after 7 of the 8 voxel values its header gives"));
    write(dir.file("more.vtk"), legacyVtk("2 2 2", 8, "short", "1 2 3 4 5 6 7 8\nSCALARS w float\nLOOKUP_TABLE default\n0 0 0 0 0 0 0 0\n"));
    EXPECT_EQ(test::voxelValues(*core::VoxelSourceFactory::open(dir.file("more.vtk"))),
              (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(AsciiVolumes, AHeaderWithoutBinaryDataIsReadAsTextAndSaysSo) {
    test::TempDir dir;
    write(dir.file("t.mha"), "ObjectType = Image\nNDims = 3\nDimSize = 2 1 1\nElementType = MET_SHORT\nElementSpacing = 1 1 1\n"
                             "ElementDataFile = LOCAL\n-7 9\n");
    auto src = core::VoxelSourceFactory::open(dir.file("t.mha"));
    EXPECT_EQ(test::readAll<std::int16_t>(*src), (std::vector<std::int16_t>{-7, 9}));
    bool said = false;
    for (const auto& w : src->warnings()) said = said || w.find("gives no BinaryData: its data are read as text") != std::string::npos;
    EXPECT_TRUE(said);
}
