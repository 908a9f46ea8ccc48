#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <random>
#include <set>

#include <dcmtk/dcmdata/dctk.h>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "dicom/DicomScanner.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/DicomSeriesWriter.h"
#include "dicom/SeriesAssembler.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {
// A CT-like int16 volume with a known geometry whose values encode the voxel index.
test::MemoryVoxelSource knownVolume(std::array<std::uint32_t, 3> dims, glm::dmat3 direction, glm::dvec3 spacing,
                                    core::ScalarType type = core::ScalarType::Int16) {
    core::VolumeGeometry g;
    g.scalarType = type;
    g.spacing = spacing;
    g.direction = direction;
    g.origin = {-101.5, 37.25, 12.0};
    g.modality = "CT";
    g.rescaleSlope = 1.0;
    g.rescaleIntercept = -1024.0;
    test::DenseVolume v;
    v.dims = dims;
    std::mt19937 rng(7);
    for (std::uint32_t k = 0; k < dims[2]; ++k)
        for (std::uint32_t j = 0; j < dims[1]; ++j)
            for (std::uint32_t i = 0; i < dims[0]; ++i)
                v.values.push_back(type == core::ScalarType::UInt8 ? double((i * 7 + j * 3 + k * 11) % 256)
                                                                   : double(int(rng() % 3000) - 1000));
    return test::MemoryVoxelSource(g, v);
}

std::vector<dicom::SeriesVolume> importFolder(const std::string& dir, std::vector<std::string>* notesOut = nullptr) {
    core::JobContext job;
    const auto scan = dicom::DicomScanner::scan({dir}, job);
    std::vector<std::string> notes;
    auto v = dicom::SeriesAssembler::assemble(scan.instances, notes);
    if (notesOut) *notesOut = notes;
    return v;
}

std::vector<double> readVolume(core::VoxelSource& s) { return test::voxelValues(s); }

// Every imported voxel, placed in patient space, lands on an original voxel with the same value.
void expectSameVolumeInPatientSpace(const dicom::SeriesVolume& v, test::MemoryVoxelSource& original) {
    dicom::DicomSeriesSource src(v);
    const auto& gi = src.geometry();
    const auto& go = original.geometry();
    ASSERT_EQ(gi.voxelCount(), go.voxelCount());
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(gi.spacing[a], go.spacing[a], 1e-6) << "axis " << a;
    EXPECT_NEAR(glm::length(gi.direction[0] - go.direction[0]), 0.0, 1e-6);
    EXPECT_NEAR(glm::length(gi.direction[1] - go.direction[1]), 0.0, 1e-6);
    EXPECT_NEAR(std::abs(glm::dot(gi.direction[2], go.direction[2])), 1.0, 1e-6);
    EXPECT_EQ(gi.rescaleSlope, go.rescaleSlope);
    EXPECT_EQ(gi.rescaleIntercept, go.rescaleIntercept);
    const auto values = readVolume(src);
    const glm::dmat4 toOriginal = glm::inverse(go.indexToPatient()) * gi.indexToPatient();
    std::size_t bad = 0;
    for (std::uint32_t k = 0; k < gi.dims[2]; ++k)
        for (std::uint32_t j = 0; j < gi.dims[1]; ++j)
            for (std::uint32_t i = 0; i < gi.dims[0]; ++i) {
                const glm::dvec4 o = toOriginal * glm::dvec4(i, j, k, 1.0);
                const long oi = std::lround(o.x), oj = std::lround(o.y), ok = std::lround(o.z);
                ASSERT_NEAR(o.x, double(oi), 1e-3);
                ASSERT_NEAR(o.z, double(ok), 1e-3);
                const double want = original.values().clamped(oi, oj, ok);
                const double got = values[(std::size_t(k) * gi.dims[1] + j) * gi.dims[0] + i];
                if (got != want && ++bad < 5) ADD_FAILURE() << "voxel " << i << "," << j << "," << k;
            }
    EXPECT_EQ(bad, 0u);
}

void shuffleFileNames(const std::vector<std::string>& files) {
    std::mt19937 rng(3);
    std::vector<std::string> names = files;
    std::shuffle(names.begin(), names.end(), rng);
    for (std::size_t i = 0; i < files.size(); ++i) std::filesystem::rename(files[i], files[i] + ".tmp");
    for (std::size_t i = 0; i < files.size(); ++i) std::filesystem::rename(files[i] + ".tmp", names[i] + ".x");
}

const glm::dmat3 kAxial(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));
const glm::dmat3 kCoronal(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
const glm::dmat3 kSagittal(glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1), glm::dvec3(-1, 0, 0));
glm::dmat3 oblique() {
    const glm::dvec3 r = glm::normalize(glm::dvec3(0.8, 0.5, 0.1));
    const glm::dvec3 c = glm::normalize(glm::cross(glm::dvec3(0.1, -0.3, 0.9), r));
    return glm::dmat3(r, c, glm::cross(r, c));
}
}  // namespace

class DicomOrientation : public ::testing::TestWithParam<std::pair<const char*, glm::dmat3>> {};

TEST_P(DicomOrientation, SeriesReimportsVoxelIdenticalWithLpsGeometryInShuffledOrder) {
    test::TempDir dir;
    auto vol = knownVolume({23, 19, 11}, GetParam().second, {0.7, 0.9, 2.5});
    core::JobContext job;
    const auto files = dicom::DicomSeriesWriter::write(vol, dir.file("s"), {}, job);
    ASSERT_EQ(files.size(), 11u);
    shuffleFileNames(files);
    const auto volumes = importFolder(dir.file("s"));
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_TRUE(volumes[0].warnings.empty()) << volumes[0].warnings.front();
    EXPECT_EQ(volumes[0].geometry.modality, "CT");
    expectSameVolumeInPatientSpace(volumes[0], vol);
}

TEST(DicomImport, ReverseStackIsSortedByPositionNotInstanceNumber) {
    // k runs against the slice normal: instance 1 is the most superior slice.
    test::TempDir dir;
    const glm::dmat3 down(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1));
    auto vol = knownVolume({9, 8, 6}, down, {1, 1, 3});
    core::JobContext job;
    dicom::DicomSeriesWriter::write(vol, dir.file("s"), {}, job);
    const auto volumes = importFolder(dir.file("s"));
    ASSERT_EQ(volumes.size(), 1u);
    // Sorted along +normal: the imported k axis points superior, its origin is the lowest slice.
    EXPECT_NEAR(volumes[0].geometry.direction[2].z, 1.0, 1e-9);
    EXPECT_NEAR(volumes[0].geometry.origin.z, 12.0 - 15.0, 1e-9);
    expectSameVolumeInPatientSpace(volumes[0], vol);
}

INSTANTIATE_TEST_SUITE_P(Orientations, DicomOrientation,
                         ::testing::Values(std::make_pair("axial", kAxial), std::make_pair("coronal", kCoronal),
                                           std::make_pair("sagittal", kSagittal),
                                           std::make_pair("oblique", oblique())),
                         [](const auto& p) { return std::string(p.param.first); });

class DicomCodec : public ::testing::TestWithParam<const char*> {
protected:
    /// Writes `volume` in the syntax under test and expects the import to give it back.
    void expectRoundTrip(test::MemoryVoxelSource& volume) {
        test::TempDir dir;
        dicom::DicomWriteOptions o;
        o.transferSyntax = GetParam();
        core::JobContext job;
        dicom::DicomSeriesWriter::write(volume, dir.file("s"), o, job);
        const auto volumes = importFolder(dir.file("s"));
        ASSERT_EQ(volumes.size(), 1u);
        expectSameVolumeInPatientSpace(volumes[0], volume);
    }
};

TEST_P(DicomCodec, EachTransferSyntaxDcmtkWritesDecodesIdentically) {
    auto vol = knownVolume({17, 13, 4}, kAxial, {0.5, 0.5, 1.0});
    expectRoundTrip(vol);
}

// Incompressible data: stored values over the whole int16 range, at random. DCMTK's default
// ("cooked") JPEG-LS encoder crashed or wrote undecodable slices on it.
TEST_P(DicomCodec, FullRangeNoiseSurvivesEachTransferSyntax) {
    auto base = knownVolume({64, 48, 3}, kAxial, {0.5, 0.5, 1.0});
    test::DenseVolume v;
    v.dims = base.geometry().dims;
    std::mt19937 rng(11);
    for (std::size_t i = 0; i < std::size_t(64 * 48 * 3); ++i) v.values.push_back(double(int(rng() % 65536) - 32768));
    core::VolumeGeometry g = base.geometry();
    g.rescaleIntercept = 0.0;
    test::MemoryVoxelSource noise(g, v);
    expectRoundTrip(noise);
}

INSTANTIATE_TEST_SUITE_P(Syntaxes, DicomCodec,
                         ::testing::Values("explicit-little", "implicit-little", "explicit-big", "deflate", "rle",
                                           "jpeg-lossless", "jpeg-ls"),
                         [](const auto& p) {
                             std::string n = p.param;
                             n.erase(std::remove(n.begin(), n.end(), '-'), n.end());
                             return n;
                         });

TEST(DicomImport, EnhancedMultiframeUsesPerFrameFunctionalGroups) {
    test::TempDir dir;
    auto vol = knownVolume({15, 12, 7}, kCoronal, {0.6, 0.6, 1.5});
    dicom::DicomWriteOptions o;
    o.enhancedMultiframe = true;
    core::JobContext job;
    const auto files = dicom::DicomSeriesWriter::write(vol, dir.file("s"), o, job);
    ASSERT_EQ(files.size(), 1u);
    const auto volumes = importFolder(dir.file("s"));
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_EQ(volumes[0].slices.size(), 7u);
    expectSameVolumeInPatientSpace(volumes[0], vol);
}

TEST(DicomImport, MissingSliceIsNamedAndInterpolated) {
    test::TempDir dir;
    auto vol = knownVolume({10, 9, 8}, kAxial, {1, 1, 2});
    core::JobContext job;
    const auto files = dicom::DicomSeriesWriter::write(vol, dir.file("s"), {}, job);
    std::filesystem::remove(files[4]);
    const auto volumes = importFolder(dir.file("s"));
    ASSERT_EQ(volumes.size(), 1u);
    ASSERT_EQ(volumes[0].warnings.size(), 1u);
    EXPECT_NE(volumes[0].warnings[0].find("1 missing slice"), std::string::npos) << volumes[0].warnings[0];
    dicom::DicomSeriesSource src(volumes[0]);
    EXPECT_EQ(src.geometry().dims[2], 8u);
    EXPECT_DOUBLE_EQ(src.geometry().spacing.z, 2.0);
    const auto v = readVolume(src);
    const auto at = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) { return v[(k * 9 + j) * 10 + i]; };
    const auto& o = vol.values();
    EXPECT_EQ(at(3, 4, 3), o.clamped(3, 4, 3));
    EXPECT_EQ(at(3, 4, 5), o.clamped(3, 4, 5));
    EXPECT_EQ(at(3, 4, 4), std::round((o.clamped(3, 4, 3) + o.clamped(3, 4, 5)) / 2));
}

TEST(DicomImport, TiltedGantryIsKeptShearedWithItsExactTransform) {
    test::TempDir dir;
    const double tilt = 15.0 * M_PI / 180.0;
    const glm::dmat3 sheared(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, std::sin(tilt), std::cos(tilt)));
    auto vol = knownVolume({12, 10, 6}, sheared, {0.8, 0.8, 2.0});
    core::JobContext job;
    dicom::DicomSeriesWriter::write(vol, dir.file("s"), {}, job);
    const auto volumes = importFolder(dir.file("s"));
    ASSERT_EQ(volumes.size(), 1u);
    ASSERT_EQ(volumes[0].warnings.size(), 1u);
    EXPECT_NE(volumes[0].warnings[0].find("gantry tilt of 15.00 degrees"), std::string::npos) << volumes[0].warnings[0];
    EXPECT_FALSE(volumes[0].resample);
    expectSameVolumeInPatientSpace(volumes[0], vol);
}

TEST(DicomImport, TwoStacksInOneSeriesBecomeTwoVolumes) {
    test::TempDir dir;
    auto axial = knownVolume({10, 10, 5}, kAxial, {1, 1, 2});
    auto scout = knownVolume({16, 12, 1}, kCoronal, {1.5, 1.5, 1});
    dicom::DicomWriteOptions o;
    o.seriesUid = "1.2.826.0.1.3680043.9.7777.1";
    o.studyUid = "1.2.826.0.1.3680043.9.7777.2";
    core::JobContext job;
    dicom::DicomSeriesWriter::write(axial, dir.file("a"), o, job);
    dicom::DicomSeriesWriter::write(scout, dir.file("b"), o, job);
    const auto volumes = importFolder(dir.path().string());
    ASSERT_EQ(volumes.size(), 2u);
    EXPECT_EQ(volumes[0].seriesUid, volumes[1].seriesUid);
    for (const auto& v : volumes) {
        ASSERT_FALSE(v.warnings.empty());
        EXPECT_NE(v.warnings[0].find("2 stacks"), std::string::npos);
        EXPECT_NE(v.warnings[0].find("mixed image sizes"), std::string::npos);
    }
    const auto& big = volumes[0].slices.size() == 5 ? volumes[0] : volumes[1];
    expectSameVolumeInPatientSpace(big, axial);
}

TEST(DicomImport, TwoFramesOfReferenceInOneSeriesAreNeverOneStack) {
    // Same series, same image size and orientation, slices that would continue each other, but
    // two frames of reference: two coordinate systems, so two volumes, each keeping its frame.
    test::TempDir dir;
    auto lower = knownVolume({10, 10, 5}, kAxial, {1, 1, 2});
    dicom::DicomWriteOptions o;
    o.seriesUid = "1.2.826.0.1.3680043.9.7777.11";
    o.studyUid = "1.2.826.0.1.3680043.9.7777.12";
    o.frameOfReferenceUid = "1.2.826.0.1.3680043.9.7777.13";
    core::JobContext job;
    dicom::DicomSeriesWriter::write(lower, dir.file("a"), o, job);
    core::VolumeGeometry g = lower.geometry();
    g.origin.z += 10.0;
    test::MemoryVoxelSource upper(g, lower.values());
    o.frameOfReferenceUid = "1.2.826.0.1.3680043.9.7777.14";
    dicom::DicomSeriesWriter::write(upper, dir.file("b"), o, job);
    const auto volumes = importFolder(dir.path().string());
    ASSERT_EQ(volumes.size(), 2u);
    std::set<std::string> frames;
    for (const auto& v : volumes) {
        EXPECT_EQ(v.slices.size(), 5u);
        dicom::DicomSeriesSource src(v);
        frames.insert(src.geometry().frameOfReferenceUid);
    }
    EXPECT_EQ(frames, (std::set<std::string>{"1.2.826.0.1.3680043.9.7777.13", "1.2.826.0.1.3680043.9.7777.14"}));
}

TEST(DicomImport, HounsfieldRescaleAndMonochrome1GoIntoTheOctree) {
    test::TempDir dir;
    auto vol = knownVolume({8, 8, 3}, kAxial, {1, 1, 1});
    core::JobContext job;
    dicom::DicomSeriesWriter::write(vol, dir.file("s"), {}, job);
    auto volumes = importFolder(dir.file("s"));
    ASSERT_EQ(volumes.size(), 1u);
    dicom::DicomSeriesSource src(volumes[0]);
    core::OctreeBuilder(core::BuildOptions{}).build(src, dir.file("v.hvo"), job);
    const auto r = core::OctreeReader::open(dir.file("v.hvo"));
    EXPECT_EQ(r->geometry().rescaleIntercept, -1024.0);
    EXPECT_EQ(r->geometry().rescaleSlope, 1.0);
    EXPECT_EQ(r->geometry().modality, "CT");
    EXPECT_FALSE(r->geometry().monochrome1);
    // A stored value v is v - 1024 HU.
    const auto b = r->readBrick(0);
    EXPECT_EQ(b.value(2, 2, 2) * r->geometry().rescaleSlope + r->geometry().rescaleIntercept,
              vol.values().clamped(0, 0, 0) - 1024.0);

    const std::string cr = "/usr/lib/python3/dist-packages/pydicom/data/test_files/dicomdirtests/77654033/CR1/6154";
    std::filesystem::create_directories(dir.file("cr"));
    std::filesystem::copy_file(cr, dir.file("cr/6154"));
    volumes = importFolder(dir.file("cr"));
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_TRUE(volumes[0].geometry.monochrome1);
}

TEST(DicomImport, AStackMixingMonochrome1And2KeepsItsValuesAndSaysHowItIsShown) {
    test::TempDir dir;
    auto vol = knownVolume({8, 8, 3}, kAxial, {1, 1, 1});
    core::JobContext job;
    const auto files = dicom::DicomSeriesWriter::write(vol, dir.file("s"), {}, job);
    ASSERT_EQ(files.size(), 3u);
    auto invert = [](const std::string& path) {  // as a scanner writing MONOCHROME1 would label it
        DcmFileFormat f;
        ASSERT_TRUE(f.loadFile(path.c_str()).good());
        ASSERT_TRUE(f.getDataset()->putAndInsertString(DCM_PhotometricInterpretation, "MONOCHROME1").good());
        ASSERT_TRUE(f.saveFile(path.c_str(), EXS_LittleEndianExplicit).good());
    };
    invert(files[0]);
    invert(files[2]);
    auto volumes = importFolder(dir.file("s"));
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_FALSE(volumes[0].geometry.monochrome1) << "shown as MONOCHROME2";
    std::string said;
    for (const auto& w : volumes[0].warnings) said += w + "\n";
    EXPECT_NE(said.find("2 of the 3 slices are MONOCHROME1"), std::string::npos) << said;
    expectSameVolumeInPatientSpace(volumes[0], vol);  // the values as stored
    invert(files[1]);
    volumes = importFolder(dir.file("s"));
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_TRUE(volumes[0].geometry.monochrome1) << "every slice MONOCHROME1";
    for (const auto& w : volumes[0].warnings) EXPECT_EQ(w.find("MONOCHROME"), std::string::npos) << w;
}
