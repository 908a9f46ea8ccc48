// Float volumes whose voxels are not all numbers (SPM's and FSL's NaN outside a mask, an
// infinity from a division): refused as they are read, naming the file, the slice and how many
// such values it holds, whatever the format; a float volume of numbers and every integer
// volume pass untouched.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>

#include "core/volume/FiniteValueSource.h"
#include "core/volume/RawVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {
using test::errorOf;

constexpr std::uint32_t kX = 5, kY = 4, kZ = 6, kN = kX * kY * kZ;

template <class T>
std::string bytesOf(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

std::vector<float> ramp() {
    std::vector<float> v(kN);
    for (std::size_t i = 0; i < kN; ++i) v[i] = float(i) * 0.5f - 20.0f;
    return v;
}

std::string nrrd(const char* type) {
    return std::string("NRRD0004\ntype: ") + type +
           "\ndimension: 3\nspace: LPS\nsizes: 5 4 6\nspacings: 1 1 1\nendian: little\nencoding: raw\n\n";
}
}  // namespace

TEST(FiniteValue, ANanIsRefusedAtItsSliceWithItsCount) {
    test::TempDir dir;
    auto v = ramp();
    v[3 * kX * kY + 2] = std::numeric_limits<float>::quiet_NaN();  // slice 3
    v[3 * kX * kY + 9] = -std::numeric_limits<float>::quiet_NaN();
    std::ofstream(dir.file("nan.nrrd"), std::ios::binary) << nrrd("float") << bytesOf(v);
    auto src = core::VoxelSourceFactory::open(dir.file("nan.nrrd"));
    std::vector<float> got(kN);
    src->readSlices(0, 3, got.data());  // the slices before it are numbers
    for (std::size_t i = 0; i < 3 * kX * kY; ++i) ASSERT_EQ(got[i], v[i]) << i;
    const auto e = errorOf([&] { src->readSlices(2, 3, got.data()); });
    EXPECT_EQ(e.rfind(dir.file("nan.nrrd") + ": slice 3 holds 2 NaN (not-a-number) values: Holovox reads only "
                                              "volumes whose every voxel is a number",
                      0),
              0u)
        << e;
}

TEST(FiniteValue, InfinitiesAreRefusedFromFloat32AndFloat64Files) {
    test::TempDir dir;
    auto v = ramp();
    v[5 * kX * kY] = std::numeric_limits<float>::infinity();
    v[5 * kX * kY + 1] = std::numeric_limits<float>::quiet_NaN();
    core::RawVoxelSource::Options o;
    o.dims = {kX, kY, kZ};
    o.element = core::FileElement::Float32;
    std::ofstream(dir.file("inf.raw"), std::ios::binary) << bytesOf(v);
    const auto e = errorOf([&] { test::readAll<float>(*core::VoxelSourceFactory::open(dir.file("inf.raw"), o)); });
    EXPECT_NE(e.find("inf.raw: slice 5 holds 1 NaN (not-a-number) value and 1 infinite value"), std::string::npos) << e;

    std::vector<double> d(v.begin(), v.end());
    d[5 * kX * kY + 1] = -std::numeric_limits<double>::infinity();  // kept as a float32 infinity, then refused
    std::ofstream(dir.file("inf.nrrd"), std::ios::binary) << nrrd("double") << bytesOf(d);
    const auto f = errorOf([&] { test::readAll<float>(*core::VoxelSourceFactory::open(dir.file("inf.nrrd"))); });
    EXPECT_NE(f.find("inf.nrrd: slice 5 holds 2 infinite values"), std::string::npos) << f;
}

TEST(FiniteValue, NumbersAndIntegerVolumesPassUntouched) {
    test::TempDir dir;
    auto v = ramp();
    v[7] = std::numeric_limits<float>::max();
    v[8] = -std::numeric_limits<float>::max();
    v[9] = std::numeric_limits<float>::denorm_min();
    std::ofstream(dir.file("ok.nrrd"), std::ios::binary) << nrrd("float") << bytesOf(v);
    const auto src = core::VoxelSourceFactory::open(dir.file("ok.nrrd"));
    ASSERT_NE(dynamic_cast<core::FiniteValueSource*>(src.get()), nullptr);
    EXPECT_EQ(src->describe(), dir.file("ok.nrrd"));
    EXPECT_EQ(test::readAll<float>(*src), v);

    std::vector<std::int16_t> s(kN);
    for (std::size_t i = 0; i < kN; ++i) s[i] = std::int16_t(int(i) * 100 - 1024);
    std::ofstream(dir.file("ct.nrrd"), std::ios::binary) << nrrd("short") << bytesOf(s);
    const auto ct = core::VoxelSourceFactory::open(dir.file("ct.nrrd"));
    EXPECT_EQ(dynamic_cast<core::FiniteValueSource*>(ct.get()), nullptr) << "an integer volume is not wrapped";
    EXPECT_EQ(test::readAll<std::int16_t>(*ct), s);
}
