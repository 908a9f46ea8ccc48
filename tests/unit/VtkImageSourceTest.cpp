// MetaImage and legacy VTK files read through the VTK reader module (loaded on first use): the
// types it widens exactly, the ones it refuses, slabs across its 32-slice reads, and broken files.
// (The factory streams plain MetaImage files itself, FileElementTest; these open the module.)
// Each file is written here by hand, so the expected voxels are known without Holovox or VTK.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <fstream>
#include <functional>
#include <memory>
#include <vector>

#include "core/base/Error.h"
#include "core/volume/VoxelSourceFactory.h"
#include "core/volume/VtkImageSource.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {
using test::errorOf;

/// A MetaImage of dims nx x ny x nz, its header `extra` lines, then `bytes` of data.
void writeMha(const std::string& path, int nx, int ny, int nz, const std::string& elementType,
              const std::string& data, const std::string& extra = "") {
    std::ofstream f(path, std::ios::binary);
    f << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n" << extra
      << "DimSize = " << nx << " " << ny << " " << nz << "\nElementType = " << elementType
      << "\nElementSpacing = 1 1 1\nElementDataFile = LOCAL\n";
    f.write(data.data(), std::streamsize(data.size()));
}

template <class T>
std::string bytesOf(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

}  // namespace

TEST(VtkImageSource, SignedBytesAreWidenedExactlyToInt16) {
    test::TempDir dir;
    std::vector<std::int8_t> v(4 * 3 * 2);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::int8_t(int(i) * 11 - 128);
    writeMha(dir.file("c.mha"), 4, 3, 2, "MET_CHAR", bytesOf(v));
    auto src = std::make_unique<core::VtkImageSource>(dir.file("c.mha"));
    ASSERT_EQ(src->geometry().scalarType, core::ScalarType::Int16);
    const auto got = test::readAll<std::int16_t>(*src);
    for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(got[i], v[i]) << "voxel " << i;
}

TEST(VtkImageSource, DoublesBecomeFloats) {
    test::TempDir dir;
    std::vector<double> v(3 * 2 * 2);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = -1000.25 + double(i) * 0.5;
    writeMha(dir.file("d.mha"), 3, 2, 2, "MET_DOUBLE", bytesOf(v));
    auto src = std::make_unique<core::VtkImageSource>(dir.file("d.mha"));
    ASSERT_EQ(src->geometry().scalarType, core::ScalarType::Float32);
    const auto got = test::readAll<float>(*src);
    for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(got[i], float(v[i])) << "voxel " << i;
}

TEST(VtkImageSource, MetaImageSlabsAreExactInAnyOrder) {
    test::TempDir dir;
    const int nx = 5, ny = 4, nz = 70;  // more than the 32 slices of a streamed read
    std::vector<std::int8_t> v(std::size_t(nx) * ny * nz);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::int8_t(int(i * 7 % 251) - 125);
    writeMha(dir.file("u.mha"), nx, ny, nz, "MET_CHAR", bytesOf(v));
    auto src = std::make_unique<core::VtkImageSource>(dir.file("u.mha"));
    ASSERT_EQ(src->geometry().scalarType, core::ScalarType::Int16);
    const std::size_t slice = std::size_t(nx) * ny;
    std::vector<std::int16_t> slab(slice * 9);
    for (std::uint32_t first : {0u, 9u, 27u, 30u, 61u}) {  // 27..35 and 30..38 cross a chunk boundary
        src->readSlices(first, 9, slab.data());
        for (std::size_t i = 0; i < slab.size(); ++i) ASSERT_EQ(slab[i], v[first * slice + i]) << "slab at " << first;
    }
    // A source whose first read starts inside the volume (VTK's MetaImage reader cannot read a
    // slab alone: asked for one, it overflowed its buffer and the program aborted).
    auto late = std::make_unique<core::VtkImageSource>(dir.file("u.mha"));
    late->readSlices(40, 9, slab.data());
    for (std::size_t i = 0; i < slab.size(); ++i) ASSERT_EQ(slab[i], v[40 * slice + i]);
}

TEST(VtkImageSource, VtiSlabsAcrossItsChunkedReadsAreExact) {
    test::TempDir dir;
    const int nx = 3, ny = 2, nz = 70;
    {
        std::ofstream f(dir.file("u.vti"));
        f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          << "<ImageData WholeExtent=\"0 " << nx - 1 << " 0 " << ny - 1 << " 0 " << nz - 1
          << "\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n<Piece Extent=\"0 " << nx - 1 << " 0 " << ny - 1 << " 0 " << nz - 1
          << "\">\n<PointData Scalars=\"v\">\n<DataArray type=\"Int16\" Name=\"v\" format=\"ascii\">\n";
        for (int i = 0; i < nx * ny * nz; ++i) f << (i * 3 - 200) << " ";
        f << "\n</DataArray>\n</PointData>\n<CellData>\n</CellData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
    }
    auto src = core::VoxelSourceFactory::open(dir.file("u.vti"));
    ASSERT_EQ(src->geometry().scalarType, core::ScalarType::Int16);
    const std::size_t slice = std::size_t(nx) * ny;
    std::vector<std::int16_t> slab(slice * 9);
    for (std::uint32_t first : {20u, 29u, 61u}) {  // 29..37 crosses a chunk boundary
        src->readSlices(first, 9, slab.data());
        for (std::size_t i = 0; i < slab.size(); ++i)
            ASSERT_EQ(slab[i], int(first * slice + i) * 3 - 200) << "slab at " << first;
    }
}

TEST(VtkImageSource, LegacyStructuredPointsGeometryAndValues) {
    test::TempDir dir;
    {
        std::ofstream f(dir.file("s.vtk"));
        f << "# vtk DataFile Version 3.0\nhand written\nASCII\nDATASET STRUCTURED_POINTS\n"
             "DIMENSIONS 3 2 2\nORIGIN 10 -20 30\nSPACING 0.5 1.5 2.5\nPOINT_DATA 12\n"
             "SCALARS v short 1\nLOOKUP_TABLE default\n";
        for (int i = 0; i < 12; ++i) f << (i * 100 - 600) << "\n";
    }
    auto src = core::VoxelSourceFactory::open(dir.file("s.vtk"));
    const auto& g = src->geometry();
    EXPECT_EQ(g.dims, (std::array<std::uint32_t, 3>{3, 2, 2}));
    EXPECT_EQ(g.spacing, glm::dvec3(0.5, 1.5, 2.5));
    EXPECT_EQ(g.origin, glm::dvec3(10, -20, 30));
    ASSERT_EQ(g.scalarType, core::ScalarType::Int16);
    const auto got = test::readAll<std::int16_t>(*src);
    for (int i = 0; i < 12; ++i) EXPECT_EQ(got[std::size_t(i)], i * 100 - 600);
}

TEST(VtkImageSource, RefusesWhatItCannotShowWithASentence) {
    test::TempDir dir;
    writeMha(dir.file("i.mha"), 2, 2, 2, "MET_INT", std::string(32, '\0'));
    EXPECT_NE(errorOf([&] { core::VtkImageSource s(dir.file("i.mha")); }).find("unsupported voxel type (int)"),
              std::string::npos);
    writeMha(dir.file("rgb.mha"), 2, 2, 2, "MET_UCHAR", std::string(24, '\0'), "ElementNumberOfChannels = 3\n");
    EXPECT_NE(errorOf([&] { core::VtkImageSource s(dir.file("rgb.mha")); }).find("only single-component"),
              std::string::npos);
    {
        std::ofstream f(dir.file("poly.vtk"));
        f << "# vtk DataFile Version 3.0\nmesh\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\n";
    }
    EXPECT_NE(errorOf([&] { core::VtkImageSource s(dir.file("poly.vtk")); }).find("not a legacy VTK structured-points"),
              std::string::npos);
    std::ofstream(dir.file("text.mha")) << "not a header at all\n";
    const std::string e = errorOf([&] { core::VtkImageSource s(dir.file("text.mha")); });
    EXPECT_EQ(e.rfind(dir.file("text.mha") + ": ", 0), 0u) << e;  // names the file
}

TEST(VtkImageSource, TruncatedDataIsAnErrorNotZeros) {
    test::TempDir dir;
    std::vector<std::int16_t> v(4 * 4 * 8, 123);
    std::string data = bytesOf(v);
    data.resize(data.size() / 2);  // half the slices are missing
    writeMha(dir.file("t.mha"), 4, 4, 8, "MET_SHORT", data);
    const std::string e = errorOf([&] {
        auto src = core::VoxelSourceFactory::open(dir.file("t.mha"));
        test::readAll<std::int16_t>(*src);
    });
    EXPECT_NE(e.find(dir.file("t.mha")), std::string::npos) << e;
    EXPECT_FALSE(e.empty());
}

TEST(VtkImageSource, ATruncatedLegacyFileIsAnErrorNotZeros) {
    // VTK's legacy reader warns "Error reading binary data!" through its output window and hands
    // back zeros for what it could not read: the module turns the warning into a refusal. (The
    // factory streams such a file itself; this is the reader it leaves the rest of VTK's files to.)
    test::TempDir dir;
    {
        std::ofstream f(dir.file("b.vtk"), std::ios::binary);
        f << "# vtk DataFile Version 3.0\nhand written\nBINARY\nDATASET STRUCTURED_POINTS\n"
             "DIMENSIONS 4 4 4\nORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 64\nSCALARS v short 1\nLOOKUP_TABLE default\n";
        for (int i = 0; i < 40; ++i) {  // 40 of the 64 big-endian values
            const char be[2] = {char(0), char(i + 1)};
            f.write(be, 2);
        }
    }
    const std::string e = errorOf([&] {
        core::VtkImageSource src(dir.file("b.vtk"));
        test::readAll<std::int16_t>(src);
    });
    EXPECT_EQ(e.rfind(dir.file("b.vtk") + ": cannot read voxel data", 0), 0u) << e;
    EXPECT_NE(e.find("Error reading binary data"), std::string::npos) << e;
}

TEST(VtkImageSource, AnExtentItsFileCannotHoldIsRefusedBeforeVtkAllocatesIt) {
    // VTK allocates the extent a header announces before reading a value: this file, whose four
    // values announce 10^13 voxels, had it take 17 GiB and fail with bad_alloc after 83 s.
    test::TempDir dir;
    auto vti = [&](const std::string& name, const std::string& extent, const std::string& fileAttributes) {
        std::ofstream(dir.file(name)) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" "
                                         "byte_order=\"LittleEndian\"" << fileAttributes << ">\n<ImageData WholeExtent=\""
                                      << extent << "\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n<Piece Extent=\"" << extent
                                      << "\">\n<PointData Scalars=\"v\">\n<DataArray type=\"Int16\" Name=\"v\" "
                                         "format=\"ascii\">\n1 2 3 4\n</DataArray>\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
    };
    vti("big.vti", "0 99999 0 99999 0 999", "");
    const auto start = std::chrono::steady_clock::now();
    std::string e = errorOf([&] { core::VoxelSourceFactory::open(dir.file("big.vti")); });
    EXPECT_EQ(e.rfind(dir.file("big.vti") + ": its extent gives 10000000000000 voxels, more than its ", 0), 0u) << e;
    EXPECT_NE(e.find(" bytes can hold uncompressed"), std::string::npos) << e;
    // Compressed data may hold far more voxels than bytes; what VTK would hold at once (32
    // slices of 10^10 voxels here) must still fit in half the machine's memory.
    vti("zlib.vti", "0 99999 0 99999 0 999", " compressor=\"vtkZLibDataCompressor\"");
    e = errorOf([&] { core::VoxelSourceFactory::open(dir.file("zlib.vti")); });
    EXPECT_EQ(e.rfind(dir.file("zlib.vti") + ": VTK's reader would hold 1192.1 GiB of it in memory at once, more than half of this machine's ", 0), 0u) << e;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
    // A small file is read as before, and one whose values are too few says so.
    vti("small.vti", "0 1 0 1 0 0", "");
    auto src = core::VoxelSourceFactory::open(dir.file("small.vti"));
    EXPECT_EQ(test::readAll<std::int16_t>(*src), (std::vector<std::int16_t>{1, 2, 3, 4}));
    vti("short.vti", "0 1 0 1 0 1", "");
    e = errorOf([&] { test::readAll<std::int16_t>(*core::VoxelSourceFactory::open(dir.file("short.vti"))); });
    EXPECT_NE(e.find("cannot read voxel data"), std::string::npos) << e;
}
