// Legacy VTK image files (.vtk, STRUCTURED_POINTS), written here by hand: the plain binary ones
// streamed by Holovox as raw big-endian data, placed by their SPACING, ORIGIN and DIRECTION; the
// others (several components, cell data) read by VTK's reader as before; broken headers
// and short data refused with a sentence that names the file. (VTK's own writer's files are
// checked against nibabel in volume_files_match_nifti.)

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <vector>

#include "core/base/Error.h"
#include "core/volume/FiniteValueSource.h"
#include "core/volume/LegacyVtkHeader.h"
#include "core/volume/RawVoxelSource.h"
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
    for (std::size_t i = 0; i < n; ++i) v[i] = std::int16_t(int(i * 37 % 4000) - 1024);
    return v;
}

std::string bigEndianBytes(const std::vector<std::int16_t>& v) {
    std::string out;
    for (const std::int16_t x : v) {
        out += char((std::uint16_t(x) >> 8) & 0xff);
        out += char(std::uint16_t(x) & 0xff);
    }
    return out;
}

void write(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

const std::string kHead = "# vtk DataFile Version 5.1\nvtk output\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 6 5 4\n";
const std::string kScalars = "POINT_DATA 120\nSCALARS scalars short\nLOOKUP_TABLE default\n";
}  // namespace

TEST(LegacyVtk, BinaryImageIsStreamedExactlyWithItsGeometry) {
    test::TempDir dir;
    const auto v = ramp(120);
    // As VTK writes it: the data, then a newline; here also a DIRECTION (no VTK keyword, taken
    // where rows and columns agree: an axis swap with a flip) and a second attribute after the
    // scalars, which is left alone.
    write(dir.file("a.vtk"), kHead + "SPACING 0.5 0.75 2\nORIGIN 10 -20 30\nDIRECTION 0 1 0 1 0 0 0 0 -1\n" + kScalars +
                                 bigEndianBytes(v) + "\nFIELD FieldData 0\n");
    const auto src = core::VoxelSourceFactory::open(dir.file("a.vtk"));
    ASSERT_NE(dynamic_cast<core::RawVoxelSource*>(src.get()), nullptr) << "streamed by Holovox, not read whole by VTK";
    const auto& g = src->geometry();
    EXPECT_EQ(g.dims, (std::array<std::uint32_t, 3>{6, 5, 4}));
    EXPECT_EQ(g.scalarType, core::ScalarType::Int16);
    EXPECT_EQ(g.spacing, glm::dvec3(0.5, 0.75, 2));
    EXPECT_EQ(g.origin, glm::dvec3(10, -20, 30));
    EXPECT_EQ(g.direction[0], glm::dvec3(0, 1, 0));
    EXPECT_EQ(g.direction[1], glm::dvec3(1, 0, 0));
    EXPECT_EQ(g.direction[2], glm::dvec3(0, 0, -1));
    EXPECT_FALSE(g.spacingAssumed);
    EXPECT_FALSE(g.orientationAssumed);
    EXPECT_EQ(test::readAll<std::int16_t>(*src), v);
    bool lps = false;
    for (const auto& w : src->warnings()) lps = lps || w.find("names no patient axes: taken as LPS") != std::string::npos;
    EXPECT_TRUE(lps) << "that a VTK file's axes are taken as LPS is said";
    bool direction = false;
    for (const auto& w : src->warnings()) direction = direction || w.find("DIRECTION is not part of VTK's legacy format") != std::string::npos;
    EXPECT_TRUE(direction);
}

TEST(LegacyVtk, ANegativeSpacingStepsBackAlongItsAxisAndNoSpacingIsFlagged) {
    test::TempDir dir;
    const auto v = ramp(120);
    write(dir.file("n.vtk"), kHead + "ASPECT_RATIO 1 -2 3\n" + kScalars + bigEndianBytes(v));
    auto src = core::VoxelSourceFactory::open(dir.file("n.vtk"));
    EXPECT_EQ(src->geometry().spacing, glm::dvec3(1, 2, 3));
    EXPECT_EQ(src->geometry().direction[1], glm::dvec3(0, -1, 0));
    EXPECT_EQ(src->geometry().origin, glm::dvec3(0, 0, 0));
    write(dir.file("s.vtk"), kHead + kScalars + bigEndianBytes(v));
    src = core::VoxelSourceFactory::open(dir.file("s.vtk"));
    EXPECT_TRUE(src->geometry().spacingAssumed);
    bool said = false;
    for (const auto& w : src->warnings()) said = said || w.find("gives no SPACING: 1 mm assumed") != std::string::npos;
    EXPECT_TRUE(said);
    EXPECT_EQ(test::readAll<std::int16_t>(*src), v);
}

TEST(LegacyVtk, EveryFixedSizeTypeIsStreamedAndWideOnesAreSaid) {
    test::TempDir dir;
    // int32 values beyond int16, big-endian: kept as float32, exactly, with the conversion said.
    std::string data;
    for (int i = 0; i < 120; ++i) {
        const std::uint32_t x = std::uint32_t(i * 100000 - 3000000);
        for (int b = 3; b >= 0; --b) data += char((x >> (8 * b)) & 0xff);
    }
    write(dir.file("i.vtk"), kHead + "POINT_DATA 120\nSCALARS v int 1\nLOOKUP_TABLE default\n" + data + "\n");
    const auto src = core::VoxelSourceFactory::open(dir.file("i.vtk"));
    const auto* checked = dynamic_cast<core::FiniteValueSource*>(src.get());  // float32: its values checked
    ASSERT_NE(checked, nullptr);
    ASSERT_NE(dynamic_cast<const core::RawVoxelSource*>(&checked->inner()), nullptr);
    ASSERT_EQ(src->geometry().scalarType, core::ScalarType::Float32);
    const auto got = test::readAll<float>(*src);
    for (int i = 0; i < 120; ++i) ASSERT_EQ(got[std::size_t(i)], float(i * 100000 - 3000000)) << i;
    bool said = false;
    for (const auto& w : src->warnings()) said = said || w.find("32-bit integers are kept as 32-bit floats") != std::string::npos;
    EXPECT_TRUE(said);
    for (const char* type : {"unsigned_char", "char", "signed_char", "unsigned_short", "unsigned_int", "vtktypeint64",
                             "vtktypeuint64", "float", "double"}) {
        const core::LegacyVtkHeader h = [&] {
            write(dir.file("t.vtk"), kHead + "POINT_DATA 120\nSCALARS v " + type + "\nLOOKUP_TABLE default\n");
            return core::LegacyVtkHeader::read(dir.file("t.vtk"));
        }();
        EXPECT_TRUE(h.streamReason.empty()) << type << ": " << h.streamReason;
    }
}

TEST(LegacyVtk, WhatHolovoxDoesNotStreamGoesToVtksReader) {
    test::TempDir dir;
    auto reasonOf = [&](const std::string& text) {
        write(dir.file("r.vtk"), text);
        return core::LegacyVtkHeader::read(dir.file("r.vtk")).streamReason;
    };
    EXPECT_EQ(reasonOf("# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 6 5 4\n" + kScalars),
              "");  // streamed by AsciiVoxelSource
    EXPECT_EQ(reasonOf("# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 6 5 4\n"
                       "POINT_DATA 120\nSCALARS v float 3\nLOOKUP_TABLE default\n"),
              "its SCALARS have 3 components");
    EXPECT_EQ(reasonOf(kHead + "POINT_DATA 120\nSCALARS v float 3\nLOOKUP_TABLE default\n"), "its SCALARS have 3 components");
    EXPECT_EQ(reasonOf(kHead + "POINT_DATA 120\nSCALARS v long\nLOOKUP_TABLE default\n"), "its SCALARS are of type long");
    EXPECT_EQ(reasonOf(kHead + "CELL_DATA 60\nSCALARS v short\nLOOKUP_TABLE default\n"), "its image data begin with cell_data");
    EXPECT_EQ(reasonOf(kHead + "POINT_DATA 120\nVECTORS v float\n"), "its first point data are vectors, not SCALARS");
    EXPECT_EQ(reasonOf("# vtk DataFile Version 3.0\nt\n" + std::string(70000, 'x') + "\nBINARY\n"),
              "its header is longer than 64 KiB");
    // An ASCII image is Holovox's to read, and its values are the file's.
    std::string ascii = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nSPACING 1 1 1\nORIGIN 0 0 0\n"
                        "POINT_DATA 8\nSCALARS v short\nLOOKUP_TABLE default\n";
    for (int i = 0; i < 8; ++i) ascii += std::to_string(i * 100 - 300) + " ";
    write(dir.file("ascii.vtk"), ascii + "\n");
    const auto src = core::VoxelSourceFactory::open(dir.file("ascii.vtk"));
    ASSERT_EQ(dynamic_cast<core::VtkImageSource*>(src.get()), nullptr);
    const auto got = test::readAll<std::int16_t>(*src);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(got[std::size_t(i)], i * 100 - 300);
    core::VtkImageSource vtk(dir.file("ascii.vtk"));  // VTK's reader, whole
    EXPECT_EQ(test::readAll<std::int16_t>(vtk), got);
}

TEST(LegacyVtk, BrokenHeadersAndShortDataAreRefusedNamingTheFile) {
    test::TempDir dir;
    const std::string body = kScalars + bigEndianBytes(ramp(120));
    auto refusal = [&](const std::string& text) {
        write(dir.file("b.vtk"), text);
        const std::string e = errorOf([&] {
            auto src = core::VoxelSourceFactory::open(dir.file("b.vtk"));
            test::readAll<std::int16_t>(*src);
        });
        EXPECT_EQ(e.rfind(dir.file("b.vtk") + ": ", 0), 0u) << e;
        return e;
    };
    auto has = [](const std::string& e, const char* part) { return e.find(part) != std::string::npos; };
    EXPECT_TRUE(has(refusal(kHead + kScalars + bigEndianBytes(ramp(119))), "need")) << "a voxel short";
    EXPECT_TRUE(has(refusal(kHead + kScalars), "need"));
    EXPECT_TRUE(has(refusal("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 6 5 0\n" + body),
                    "DIMENSIONS are not three whole numbers"));
    EXPECT_TRUE(has(refusal("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 6 5 4.5\n" + body),
                    "DIMENSIONS are not three whole numbers"));
    EXPECT_TRUE(has(refusal(kHead + "SPACING 1 nan 1\n" + body), "SPACING is not 3 numbers"));
    EXPECT_TRUE(has(refusal(kHead + "SPACING 1 0 1\n" + body), "SPACING has a zero"));
    EXPECT_TRUE(has(refusal(kHead + "DIRECTION 1 1 0 0 0 0 0 0 1\n" + body), "dependent directions"));
    EXPECT_TRUE(has(refusal(kHead + "DIRECTION 2 0 0 0 1 0 0 0 1\n" + body), "not a unit direction"));
    // DIRECTION on data VTK's reader would read (three components): it refuses the keyword, so
    // the file is refused here in words of its own.
    EXPECT_TRUE(has(refusal(kHead + "DIRECTION 1 0 0 0 1 0 0 0 1\nPOINT_DATA 120\nSCALARS v short 3\nLOOKUP_TABLE default\n"),
                    "refuses it"));
    // A rotation reads differently by rows and by columns: VTK defines neither.
    EXPECT_TRUE(has(refusal(kHead + "DIRECTION 0 -1 0 1 0 0 0 0 1\n" + body), "by rows or by columns is defined nowhere"));
    EXPECT_TRUE(has(refusal(kHead + "POINT_DATA 119\nSCALARS v short\nLOOKUP_TABLE default\n" + bigEndianBytes(ramp(119))),
                    "POINT_DATA 119 is not the 120 points"));
    EXPECT_TRUE(has(refusal("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nPOINT_DATA 8\n"),
                    "no DIMENSIONS"));
    EXPECT_TRUE(has(refusal("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 6 5 4\n"),
                    "ends before its POINT_DATA"));
    EXPECT_TRUE(has(refusal(kHead + "POINT_DATA 120\nSCALARS v short\nLOOKUP_TABLE default"), "ends before its data"));
    EXPECT_TRUE(has(refusal("# vtk DataFile Version 3.0\nt\nGZIP\n"), "not ASCII or BINARY"));
    EXPECT_TRUE(has(refusal("not a vtk file\n"), "not a legacy VTK file"));
    EXPECT_TRUE(has(refusal(std::string(100000, 'z')), "not a legacy VTK file"));
}
