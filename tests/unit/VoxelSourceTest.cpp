#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "core/base/Error.h"
#include "core/volume/NrrdWriter.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/volume/RawVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {

using test::errorOf;

glm::dvec3 patientOf(const core::VolumeGeometry& g, std::size_t linear) {
    const std::size_t i = linear % g.dims[0], j = linear / g.dims[0] % g.dims[1], k = linear / g.dims[0] / g.dims[1];
    return glm::dvec3(g.indexToPatient() * glm::dvec4(double(i), double(j), double(k), 1.0));
}

// A NIfTI-1 single file with one marker voxel (value 200) at (mi, mj, mk), written by hand.
void writeNifti(const std::string& path, std::array<short, 3> dims, std::array<int, 3> marker, float qfac,
                std::array<float, 3> pixdim, bool sform, std::array<float, 12> srow, std::array<float, 3> qoffset) {
    char h[352] = {};
    auto put = [&](int off, auto v) { std::memcpy(h + off, &v, sizeof v); };
    put(0, 348);
    short dim[8] = {3, dims[0], dims[1], dims[2], 1, 1, 1, 1};
    std::memcpy(h + 40, dim, sizeof dim);
    put(70, short(2));  // DT_UNSIGNED_CHAR
    put(72, short(8));
    float pd[8] = {qfac, pixdim[0], pixdim[1], pixdim[2], 1, 1, 1, 1};
    std::memcpy(h + 76, pd, sizeof pd);
    put(108, 352.0f);
    put(112, 1.0f);
    put(252, short(sform ? 0 : 1));  // qform_code
    put(254, short(sform ? 1 : 0));  // sform_code
    put(268, qoffset[0]);
    put(272, qoffset[1]);
    put(276, qoffset[2]);
    std::memcpy(h + 280, srow.data(), sizeof(float) * 12);
    std::memcpy(h + 344, "n+1\0", 4);
    std::vector<unsigned char> data(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]), 0);
    data[(std::size_t(marker[2]) * std::size_t(dims[1]) + std::size_t(marker[1])) * std::size_t(dims[0]) +
         std::size_t(marker[0])] = 200;
    std::ofstream f(path, std::ios::binary);
    f.write(h, sizeof h);
    f.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
}

std::size_t markerIndex(const std::vector<std::uint8_t>& v) {
    return std::size_t(std::find(v.begin(), v.end(), 200) - v.begin());
}
}  // namespace

TEST(RawVoxelSource, ReadsBigEndianAndRejectsWrongSizes) {
    test::TempDir dir;
    std::vector<unsigned char> bytes;
    for (int v = 0; v < 5 * 4 * 3; ++v) {
        const auto x = std::uint16_t(v * 300 - 2000);
        bytes.push_back(std::uint8_t(x >> 8));
        bytes.push_back(std::uint8_t(x & 0xff));
    }
    std::ofstream(dir.file("v.raw"), std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), 120);
    core::RawVoxelSource::Options o;
    o.dims = {5, 4, 3};
    o.element = core::FileElement::Int16;
    o.bigEndian = true;
    core::RawVoxelSource src(dir.file("v.raw"), o);
    const auto v = test::readAll<std::int16_t>(src);
    for (int i = 0; i < 60; ++i) ASSERT_EQ(v[std::size_t(i)], std::int16_t(i * 300 - 2000));

    o.dims = {5, 4, 4};
    const auto e = errorOf([&] { core::RawVoxelSource(dir.file("v.raw"), o); });
    EXPECT_NE(e.find(dir.file("v.raw")), std::string::npos) << e;
    EXPECT_NE(e.find("need 160 bytes but the file has 120"), std::string::npos) << e;
}

TEST(NrrdWriter, PhantomRoundTripsThroughNrrdWithGeometry) {
    test::TempDir dir;
    core::PhantomVoxelSource p({20, 16, 12}, 9, {300.0, 200.0, 120.0});
    core::JobContext job;
    core::NrrdWriter::write(p, dir.file("p.nrrd"), job);
    auto src = core::VoxelSourceFactory::open(dir.file("p.nrrd"));
    const auto& g = src->geometry();
    EXPECT_EQ(g.dims, p.geometry().dims);
    for (int a = 0; a < 3; ++a) {
        EXPECT_DOUBLE_EQ(g.spacing[a], p.geometry().spacing[a]);
        EXPECT_DOUBLE_EQ(g.origin[a], p.geometry().origin[a]);
    }
    EXPECT_EQ(g.direction, glm::dmat3(1.0));
    EXPECT_EQ(test::readAll<std::int16_t>(*src), test::readAll<std::int16_t>(p));
}

TEST(VtkImageSource, NiftiSformIsConvertedFromRasToLps) {
    test::TempDir dir;
    // i -> -x (RAS), j -> +z, k -> +y: a permuted, flipped sform.
    writeNifti(dir.file("s.nii"), {4, 3, 2}, {1, 2, 1}, 1.0f, {2.0f, 1.5f, 3.0f}, true,
               {-2, 0, 0, 10, 0, 0, 3, 20, 0, 1.5f, 0, 30}, {0, 0, 0});
    auto src = core::VoxelSourceFactory::open(dir.file("s.nii"));
    const auto v = test::readAll<std::uint8_t>(*src);
    const auto lps = patientOf(src->geometry(), markerIndex(v));
    // RAS of voxel (1,2,1) = (-2+10, 3+20, 3+30) -> LPS (-8, -23, 33).
    EXPECT_NEAR(lps.x, -8.0, 1e-4);
    EXPECT_NEAR(lps.y, -23.0, 1e-4);
    EXPECT_NEAR(lps.z, 33.0, 1e-4);
}

TEST(VtkImageSource, NiftiQformWithNegativeQfacKeepsLeftAndRight) {
    test::TempDir dir;
    writeNifti(dir.file("q.nii"), {5, 4, 3}, {2, 1, 1}, -1.0f, {1.0f, 1.0f, 2.0f}, false, {}, {5, 6, 7});
    auto src = core::VoxelSourceFactory::open(dir.file("q.nii"));
    const auto v = test::readAll<std::uint8_t>(*src);
    const auto lps = patientOf(src->geometry(), markerIndex(v));
    // RAS = (2 + 5, 1 + 6, -1 * 2 * 1 + 7) = (7, 7, 5) -> LPS (-7, -7, 5).
    EXPECT_NEAR(lps.x, -7.0, 1e-4);
    EXPECT_NEAR(lps.y, -7.0, 1e-4);
    EXPECT_NEAR(lps.z, 5.0, 1e-4);
}

TEST(VtkImageSource, MetaImageOriginSpacingAndValues) {
    test::TempDir dir;
    {
        std::ofstream f(dir.file("m.mha"), std::ios::binary);
        f << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
             "DimSize = 4 3 2\nElementType = MET_SHORT\nElementSpacing = 0.5 0.75 2\nOffset = 1 2 3\n"
             "ElementDataFile = LOCAL\n";
        for (short s = 0; s < 24; ++s) {
            const short x = short(s * 10 - 100);
            f.write(reinterpret_cast<const char*>(&x), 2);
        }
    }
    auto src = core::VoxelSourceFactory::open(dir.file("m.mha"));
    const auto& g = src->geometry();
    EXPECT_EQ(g.dims, (std::array<std::uint32_t, 3>{4, 3, 2}));
    EXPECT_EQ(g.spacing, glm::dvec3(0.5, 0.75, 2.0));
    EXPECT_EQ(g.origin, glm::dvec3(1, 2, 3));
    EXPECT_EQ(g.scalarType, core::ScalarType::Int16);
    const auto v = test::readAll<std::int16_t>(*src);
    for (int i = 0; i < 24; ++i) EXPECT_EQ(v[std::size_t(i)], i * 10 - 100);
}

TEST(VtkImageSource, MriTemplateGeometryIsLps) {
    const std::string path = "/usr/share/mricron/templates/ch2better.nii.gz";
    ASSERT_TRUE(std::filesystem::exists(path)) << "installer/install-deps.sh installs mricron-data";
    auto src = core::VoxelSourceFactory::open(path);
    const auto& g = src->geometry();
    EXPECT_EQ(g.dims, (std::array<std::uint32_t, 3>{301, 370, 316}));
    EXPECT_EQ(g.scalarType, core::ScalarType::UInt8);
    EXPECT_EQ(g.spacing, glm::dvec3(0.5, 0.5, 0.5));
    // Identity RAS sform: i runs towards the patient's right, i.e. -x in LPS.
    EXPECT_EQ(g.direction[0], glm::dvec3(-1, 0, 0));
    EXPECT_EQ(g.direction[1], glm::dvec3(0, -1, 0));
    EXPECT_EQ(g.direction[2], glm::dvec3(0, 0, 1));
    EXPECT_EQ(g.origin, glm::dvec3(75.0, 107.0, -69.5));
}

TEST(VoxelSourceFactory, ClearErrorsForUnknownOrMissingInput) {
    test::TempDir dir;
    EXPECT_NE(errorOf([&] { core::VoxelSourceFactory::open(dir.file("none.nii")); }).find("no such file"),
              std::string::npos);
    std::ofstream(dir.file("x.bin")) << "abc";
    EXPECT_NE(errorOf([&] { core::VoxelSourceFactory::open(dir.file("x.bin")); }).find("--dims"), std::string::npos);
    std::ofstream(dir.file("bad.nii")) << "not nifti at all";
    EXPECT_NE(errorOf([&] { core::VoxelSourceFactory::open(dir.file("bad.nii")); }).find("bad.nii"),
              std::string::npos);
    EXPECT_THROW(core::VoxelSourceFactory::parseDims("12x0x3"), core::Error);
    EXPECT_THROW(core::VoxelSourceFactory::parseDims("12x4"), core::Error);
    EXPECT_EQ(core::VoxelSourceFactory::parseDims("1x2x3"), (std::array<std::uint32_t, 3>{1, 2, 3}));
}

TEST(PhantomVoxelSource, DeterministicHounsfieldAnatomyWithHeartOnThePatientsLeft) {
    core::PhantomVoxelSource a({100, 100, 100}, 11), b({100, 100, 100}, 11), c({100, 100, 100}, 12);
    EXPECT_EQ(test::readAll<std::int16_t>(a), test::readAll<std::int16_t>(b));
    EXPECT_NE(test::readAll<std::int16_t>(a), test::readAll<std::int16_t>(c));
    EXPECT_EQ(a.geometry().modality, "CT");
    EXPECT_LT(a.voxel(1, 1, 50), -900);              // air outside the body
    EXPECT_GT(a.voxel(56, 43, 61), 180);             // contrast-filled heart at +x (patient's left)
    EXPECT_LT(a.voxel(43, 43, 61), 120);             // mirror position on the right: no heart
    EXPECT_GT(a.voxel(50, 68 + 2, 50 + 1), -50);     // spine region is not air
    EXPECT_LT(a.voxel(25, 51, 71), -700);            // right lung
    EXPECT_LT(a.voxel(74, 51, 71), -700);            // left lung
}
