// Element types that Holovox does not store as they are (int8, 32- and 64-bit integers,
// float64), in raw, NRRD (raw and gzip), MetaImage (plain and zlib) and NIfTI files written here
// by hand: each value kept exactly or as the nearest float32, with a warning where that may
// change it, and a float64 beyond float32's range refused naming the slice.

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>

#include "core/volume/FileElement.h"
#include "core/volume/MetaImageHeader.h"
#include "core/volume/RawVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {
using test::errorOf;

constexpr std::uint32_t kX = 5, kY = 4, kZ = 6, kN = kX * kY * kZ;

/// `values` as the bytes of T in the given byte order.
template <class T>
std::string bytesOf(const std::vector<T>& values, bool bigEndian) {
    std::string out(values.size() * sizeof(T), '\0');
    std::memcpy(out.data(), values.data(), out.size());
    if (bigEndian)
        for (std::size_t i = 0; i < out.size(); i += sizeof(T)) std::reverse(out.begin() + long(i), out.begin() + long(i + sizeof(T)));
    return out;
}

template <class T>
std::vector<T> valuesOf(std::initializer_list<double> seeds) {
    std::vector<T> v(kN);
    const std::vector<double> s(seeds);
    for (std::size_t i = 0; i < kN; ++i) v[i] = T(s[i % s.size()]);
    return v;
}

std::string zlibOf(const std::string& raw) {
    uLongf n = compressBound(uLong(raw.size()));
    std::string out(n, '\0');
    EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(raw.data()),
                        uLong(raw.size()), 6),
              Z_OK);
    out.resize(n);
    return out;
}

bool hasWarning(const core::VoxelSource& s, const std::string& text) {
    for (const auto& w : s.warnings())
        if (w.find(text) != std::string::npos) return true;
    return false;
}
}  // namespace

TEST(FileElement, NamesSizesAndStoredTypes) {
    using E = core::FileElement;
    for (E e : {E::Int8, E::UInt8, E::Int16, E::UInt16, E::Int32, E::UInt32, E::Int64, E::UInt64, E::Float32, E::Float64})
        EXPECT_EQ(core::parseFileElement(core::elementName(e)), e) << core::elementName(e);
    EXPECT_EQ(core::parseFileElement("double"), E::Float64);
    EXPECT_EQ(core::elementSize(E::Int64), 8u);
    EXPECT_EQ(core::storedTypeOf(E::Int8), core::ScalarType::Int16);
    EXPECT_EQ(core::storedTypeOf(E::UInt32), core::ScalarType::Float32);
    EXPECT_EQ(core::storedTypeOf(E::UInt16), core::ScalarType::UInt16);
    EXPECT_EQ(core::conversionWarning(E::Int8), "");
    EXPECT_NE(core::conversionWarning(E::Int64).find("64-bit integers are kept as 32-bit floats"), std::string::npos);
    const auto e = errorOf([] { core::parseFileElement("complex"); });
    EXPECT_NE(e.find("'complex'"), std::string::npos) << e;
    EXPECT_NE(e.find("int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32, float64"), std::string::npos) << e;
}

TEST(FileElement, DecodingConvertsInPlaceAndStopsAtAFloat64BeyondFloat32) {
    std::vector<std::int8_t> i8{-128, -1, 0, 1, 127};
    std::vector<std::int16_t> wide(i8.size());
    std::vector<unsigned char> in(i8.size() * 2);
    std::memcpy(in.data(), i8.data(), i8.size());
    ASSERT_EQ(core::decodeElements(in.data(), i8.size(), core::FileElement::Int8, false, in.data()), i8.size());
    std::memcpy(wide.data(), in.data(), in.size());  // widened in place, from the end
    EXPECT_EQ(wide, (std::vector<std::int16_t>{-128, -1, 0, 1, 127}));

    std::vector<double> f64{1.5, -2.25, 3.0e38, -1.0e39, 7.0};
    std::vector<float> out(f64.size(), -9.0f);
    std::string bytes = bytesOf(f64, true);
    EXPECT_EQ(core::decodeElements(reinterpret_cast<unsigned char*>(bytes.data()), f64.size(), core::FileElement::Float64,
                                   true, out.data()),
              3u);
    EXPECT_EQ(out[0], 1.5f);
    EXPECT_EQ(out[1], -2.25f);
    EXPECT_EQ(out[2], 3.0e38f);

    std::vector<std::uint64_t> u64{0, 16777217, 18446744073709551615ull};
    std::vector<float> o64(3);
    bytes = bytesOf(u64, false);
    core::decodeElements(reinterpret_cast<unsigned char*>(bytes.data()), 3, core::FileElement::UInt64, false, o64.data());
    EXPECT_EQ(o64, (std::vector<float>{0.0f, 16777216.0f, 18446744073709551616.0f}));  // the nearest floats
}

TEST(FileElement, RawFilesOfEveryWideTypeAreConvertedSlabBySlab) {
    test::TempDir dir;
    core::RawVoxelSource::Options o;
    o.dims = {kX, kY, kZ};
    for (bool big : {false, true}) {
        o.bigEndian = big;
        const auto i8 = valuesOf<std::int8_t>({-128, -7, 0, 3, 127});
        std::ofstream(dir.file("i8.raw"), std::ios::binary) << bytesOf(i8, big);
        o.element = core::FileElement::Int8;
        core::RawVoxelSource a(dir.file("i8.raw"), o);
        EXPECT_EQ(a.geometry().scalarType, core::ScalarType::Int16);
        EXPECT_EQ(test::readAll<std::int16_t>(a), std::vector<std::int16_t>(i8.begin(), i8.end()));

        const auto i32 = valuesOf<std::int32_t>({-2147483648.0, -1, 0, 16777216, 2147483647.0});
        std::ofstream(dir.file("i32.raw"), std::ios::binary) << bytesOf(i32, big);
        o.element = core::FileElement::Int32;
        core::RawVoxelSource b(dir.file("i32.raw"), o);
        const auto got = test::readAll<float>(b);
        for (std::size_t i = 0; i < kN; ++i) ASSERT_EQ(got[i], float(i32[i])) << i;

        const auto f64 = valuesOf<double>({-1024.5, 0.1, 3071.25, 1e-300, -0.0});
        std::ofstream(dir.file("f64.raw"), std::ios::binary) << bytesOf(f64, big);
        o.element = core::FileElement::Float64;
        core::RawVoxelSource c(dir.file("f64.raw"), o);
        std::vector<float> part(kX * kY * 2);
        c.readSlices(3, 2, part.data());  // from the middle
        for (std::size_t i = 0; i < part.size(); ++i) ASSERT_EQ(part[i], float(f64[3 * kX * kY + i])) << i;
    }
    // the size is the file's elements', not the stored ones'
    o.element = core::FileElement::Float64;
    o.dims = {kX, kY, kZ + 1};
    const auto e = errorOf([&] { core::RawVoxelSource(dir.file("f64.raw"), o); });
    EXPECT_NE(e.find("float64 need 1120 bytes but the file has 960"), std::string::npos) << e;
}

TEST(FileElement, AFloat64BeyondFloat32IsRefusedAtItsSlice) {
    test::TempDir dir;
    auto f64 = valuesOf<double>({1, 2, 3});
    f64[4 * kX * kY + 7] = 1e300;  // slice 4
    std::ofstream(dir.file("big.nrrd"), std::ios::binary)
        << "NRRD0004\ntype: double\ndimension: 3\nspace: LPS\nsizes: 5 4 6\nendian: little\nencoding: raw\n\n"
        << bytesOf(f64, false);
    auto src = core::VoxelSourceFactory::open(dir.file("big.nrrd"));
    std::vector<float> v(kN);
    src->readSlices(0, 4, v.data());  // the slices before it are fine
    const auto e = errorOf([&] { src->readSlices(0, kZ, v.data()); });
    EXPECT_NE(e.find(dir.file("big.nrrd") + ": slice 4 holds a value beyond what a 32-bit float can hold"),
              std::string::npos)
        << e;
}

TEST(FileElement, NrrdOfEveryTeemTypeIsStreamed) {
    test::TempDir dir;
    const auto f64 = valuesOf<double>({-1000.75, 0.5, 2.0e20, 40.125});
    std::ofstream(dir.file("d.nrrd"), std::ios::binary)
        << "NRRD0004\ntype: double\ndimension: 3\nspace: LPS\nsizes: 5 4 6\nendian: big\nencoding: raw\n\n"
        << bytesOf(f64, true);
    auto d = core::VoxelSourceFactory::open(dir.file("d.nrrd"));
    EXPECT_EQ(d->geometry().scalarType, core::ScalarType::Float32);
    EXPECT_TRUE(hasWarning(*d, dir.file("d.nrrd") + ": its 64-bit floats are kept as 32-bit floats"));
    const auto dv = test::readAll<float>(*d);
    for (std::size_t i = 0; i < kN; ++i) ASSERT_EQ(dv[i], float(f64[i])) << i;

    const auto i8 = valuesOf<std::int8_t>({-100, 5, 120});
    std::ofstream(dir.file("c.nrrd"), std::ios::binary)
        << "NRRD0004\ntype: signed char\ndimension: 3\nspace: RAS\nsizes: 5 4 6\nencoding: gzip\n\n";
    gzFile gz = gzopen(dir.file("c.nrrd").c_str(), "ab");
    const std::string raw = bytesOf(i8, false);
    ASSERT_EQ(gzwrite(gz, raw.data(), unsigned(raw.size())), int(raw.size()));
    gzclose(gz);
    auto c = core::VoxelSourceFactory::open(dir.file("c.nrrd"));
    EXPECT_FALSE(hasWarning(*c, "kept as"));  // int8 is kept exactly
    EXPECT_EQ(test::readAll<std::int16_t>(*c), std::vector<std::int16_t>(i8.begin(), i8.end()));

    for (const char* type : {"int", "uint", "long long", "ulonglong"}) {
        std::ofstream(dir.file("t.nrrd"), std::ios::binary)
            << "NRRD0004\ntype: " << type << "\ndimension: 3\nspace: LPS\nsizes: 1 1 1\nendian: little\nencoding: raw\n\n"
            << std::string(std::strchr(type, 'l') ? 8 : 4, '\x01');
        auto t = core::VoxelSourceFactory::open(dir.file("t.nrrd"));
        EXPECT_EQ(t->geometry().scalarType, core::ScalarType::Float32) << type;
        EXPECT_TRUE(hasWarning(*t, "-bit integers are kept as 32-bit floats")) << type;
    }
    std::ofstream(dir.file("none.nrrd"), std::ios::binary) << "NRRD0004\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n"
                                                            << "xx";
    const auto e = errorOf([&] { core::VoxelSourceFactory::open(dir.file("none.nrrd")); });
    EXPECT_NE(e.find("NRRD header has no type"), std::string::npos) << e;
}

TEST(FileElement, MetaImageOfEveryMetaIoTypeIsStreamedByHolovox) {
    test::TempDir dir;
    const auto head = [](const char* type) {
        return std::string("ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = 5 4 6\nElementType = ") + type +
               "\nElementSpacing = 1 1 2\n";
    };
    const auto f64 = valuesOf<double>({-3.5, 1e-3, 123456.789});
    std::ofstream(dir.file("d.mha"), std::ios::binary)
        << head("MET_DOUBLE") << "BinaryDataByteOrderMSB = True\nElementDataFile = LOCAL\n" << bytesOf(f64, true);
    EXPECT_EQ(core::MetaImageHeader::read(dir.file("d.mha")).streamReason, "");
    auto d = core::VoxelSourceFactory::open(dir.file("d.mha"));
    const auto dv = test::readAll<float>(*d);
    for (std::size_t i = 0; i < kN; ++i) ASSERT_EQ(dv[i], float(f64[i])) << i;
    EXPECT_TRUE(hasWarning(*d, "64-bit floats are kept as 32-bit floats"));

    const auto i8 = valuesOf<std::int8_t>({-128, 0, 127, -3});
    const std::string z = zlibOf(bytesOf(i8, false));
    std::ofstream(dir.file("c.mha"), std::ios::binary)
        << head("MET_CHAR") << "CompressedData = True\nCompressedDataSize = " << z.size() << "\nElementDataFile = LOCAL\n" << z;
    auto c = core::VoxelSourceFactory::open(dir.file("c.mha"));
    EXPECT_EQ(test::readAll<std::int16_t>(*c), std::vector<std::int16_t>(i8.begin(), i8.end()));

    const auto i64 = valuesOf<std::int64_t>({-9007199254740993.0, 42, 0});
    std::ofstream(dir.file("l.mhd")) << head("MET_LONG_LONG") << "ElementDataFile = l.raw\n";
    std::ofstream(dir.file("l.raw"), std::ios::binary) << bytesOf(i64, false);
    auto l = core::VoxelSourceFactory::open(dir.file("l.mhd"));
    const auto lv = test::readAll<float>(*l);
    for (std::size_t i = 0; i < kN; ++i) ASSERT_EQ(lv[i], float(i64[i])) << i;

    // MET_LONG is MetaIO's 32-bit integer: 8 bytes per voxel would be the wrong size
    std::ofstream(dir.file("w.mhd")) << head("MET_LONG") << "ElementDataFile = l.raw\n";
    const auto e = errorOf([&] { core::VoxelSourceFactory::open(dir.file("w.mhd")); });
    EXPECT_NE(e.find("need 480 bytes but the file has 960"), std::string::npos) << e;
}

TEST(FileElement, NiftiFloat64IsConvertedWithAWarning) {
    test::TempDir dir;
    // A NIfTI-1 header by hand: 5x4x6 float64, little-endian, pixdim 1, sform_code 0, qform_code 0.
    std::string h(352, '\0');
    auto put = [&](std::size_t at, auto v) { std::memcpy(h.data() + at, &v, sizeof v); };
    put(0, std::int32_t(348));
    const std::int16_t dim[8] = {3, kX, kY, kZ, 1, 1, 1, 1};
    std::memcpy(h.data() + 40, dim, sizeof dim);
    put(70, std::int16_t(64));
    put(72, std::int16_t(64));
    const float pixdim[8] = {1, 1, 1, 2, 1, 1, 1, 1};
    std::memcpy(h.data() + 76, pixdim, sizeof pixdim);
    put(108, 352.0f);
    put(112, 1.0f);  // scl_slope
    std::memcpy(h.data() + 344, "n+1", 4);
    const auto f64 = valuesOf<double>({-0.125, 77.7, 1e10});
    std::ofstream(dir.file("d.nii"), std::ios::binary) << h << bytesOf(f64, false);
    auto src = core::VoxelSourceFactory::open(dir.file("d.nii"));
    const auto v = test::readAll<float>(*src);
    for (std::size_t i = 0; i < kN; ++i) ASSERT_EQ(v[i], float(f64[i])) << i;
    EXPECT_TRUE(hasWarning(*src, dir.file("d.nii") + ": its 64-bit floats are kept as 32-bit floats"));
}
