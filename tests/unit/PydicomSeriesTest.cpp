// Series written by pydicom (tests/support/dicom_cases.py), an independent writer.
// Images that share positions (multi-echo, diffusion, dynamic), in shuffled order, are split
// into volumes as dcm2niix splits them, and each volume is compared voxel by voxel with
// dcm2niix's NIfTI for the same files (placed through each one's own geometry, so a flipped
// axis or a swapped slice shows). Images nothing tells apart are refused, never mixed. Then the
// geometry and value cases whose answer is known by construction: an off-line slice, missing
// spacing and orientation, a three-plane enhanced localizer, a single-frame enhanced object,
// RT dose offsets and scaling, 32-bit unsigned pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <regex>
#include <sstream>

#include <glm/matrix.hpp>

#include "core/octree/OctreeReader.h"
#include "core/volume/NiftiVoxelSource.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomScanner.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/SeriesAssembler.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StudyDatabase.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"
#include "tests/support/VoxelValues.h"

using namespace hvx;

namespace {

std::vector<double> physical(core::VoxelSource& s) { return test::voxelValues(s, true); }

bool anyContains(const std::vector<std::string>& v, const std::string& part) {
    for (const auto& s : v)
        if (s.find(part) != std::string::npos) return true;
    return false;
}

/// Every voxel of `ours` placed in `theirs` by the two geometries: the index found must be a
/// whole voxel of theirs, holding the same value.
void expectSameVoxels(core::VoxelSource& ours, core::VoxelSource& theirs) {
    const auto& a = ours.geometry();
    const auto& b = theirs.geometry();
    ASSERT_EQ(a.voxelCount(), b.voxelCount());
    const auto va = physical(ours), vb = physical(theirs);
    const glm::dmat4 toTheirs = glm::inverse(b.indexToPatient()) * a.indexToPatient();
    std::size_t misplaced = 0, wrong = 0;
    for (std::uint32_t k = 0; k < a.dims[2]; ++k)
        for (std::uint32_t j = 0; j < a.dims[1]; ++j)
            for (std::uint32_t i = 0; i < a.dims[0]; ++i) {
                const glm::dvec4 t = toTheirs * glm::dvec4(i, j, k, 1);
                long idx[3];
                bool ok = true;
                for (int c = 0; c < 3; ++c) {
                    idx[c] = std::lround(t[c]);
                    ok = ok && std::abs(t[c] - double(idx[c])) < 1e-3 && idx[c] >= 0 && idx[c] < long(b.dims[std::size_t(c)]);
                }
                if (!ok) {
                    ++misplaced;
                    continue;
                }
                const std::size_t ia = (std::size_t(k) * a.dims[1] + j) * a.dims[0] + i;
                const std::size_t ib = (std::size_t(idx[2]) * b.dims[1] + std::size_t(idx[1])) * b.dims[0] + std::size_t(idx[0]);
                if (std::abs(va[ia] - vb[ib]) > 1e-3) ++wrong;
            }
    EXPECT_EQ(misplaced, 0u) << "voxels that land between or outside dcm2niix's";
    EXPECT_EQ(wrong, 0u) << "voxels whose values differ from dcm2niix's";
}

class PydicomSeries : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = std::make_unique<test::TempDir>();
        const auto r = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) + "/tests/support/dicom_cases.py " +
                                        dir_->file("dcm"));
        log_ = r.output;
        ok_ = r.exitCode == 0;
        for (const std::string c : {"echo", "diffusion", "dynamic", "gated", "echo-te"}) {
            std::filesystem::create_directories(dir_->file("nii/" + c));
            const auto n = test::runCommand("dcm2niix -z n -f %s -o " + dir_->file("nii/" + c) + " " + dir_->file("dcm/" + c));
            ok_ = ok_ && n.exitCode == 0;
            log_ += n.output;
        }
    }
    static void TearDownTestSuite() { dir_.reset(); }
    void SetUp() override { ASSERT_TRUE(ok_) << "pydicom or dcm2niix failed (installer/install-deps.sh installs both):\n" << log_; }

    static std::vector<dicom::SeriesVolume> import(const std::string& name, std::vector<std::string>* notes = nullptr) {
        core::JobContext job;
        const auto scan = dicom::DicomScanner::scan({dir_->file("dcm/" + name)}, job);
        std::vector<std::string> n;
        auto v = dicom::SeriesAssembler::assemble(scan.instances, n);
        if (notes) *notes = n;
        return v;
    }
    static std::string nii(const std::string& name) { return dir_->file("nii/" + name); }

    static std::unique_ptr<test::TempDir> dir_;
    static std::string log_;
    static bool ok_;
};
std::unique_ptr<test::TempDir> PydicomSeries::dir_;
std::string PydicomSeries::log_;
bool PydicomSeries::ok_ = false;

}  // namespace

TEST_F(PydicomSeries, DualEchoBecomesTwoVolumesLikeDcm2niixE1E2) {
    const auto volumes = import("echo");
    ASSERT_EQ(volumes.size(), 2u);
    EXPECT_EQ(volumes[0].varying, "echo 1 (TE 10 ms)");
    EXPECT_EQ(volumes[1].varying, "echo 2 (TE 20 ms)");
    for (int e = 0; e < 2; ++e) {
        SCOPED_TRACE(e);
        EXPECT_EQ(volumes[std::size_t(e)].geometry.dims[2], 12u);
        EXPECT_TRUE(volumes[std::size_t(e)].warnings.empty()) << volumes[std::size_t(e)].warnings.front();
        dicom::DicomSeriesSource ours(volumes[std::size_t(e)]);
        core::NiftiVoxelSource theirs(nii("echo/7_e" + std::to_string(e + 1) + ".nii"));
        expectSameVoxels(ours, theirs);
    }
}

TEST_F(PydicomSeries, ThreeBValuesBecomeThreeVolumesInDcm2niixOrder) {
    const auto volumes = import("diffusion");
    ASSERT_EQ(volumes.size(), 3u);
    EXPECT_EQ(volumes[0].varying, "b 0");
    EXPECT_EQ(volumes[1].varying, "b 500 (0.6, 0.8, 0)");
    EXPECT_EQ(volumes[2].varying, "b 1000 (0.6, 0.8, 0)");
    std::ifstream bval(nii("diffusion/7.bval"));
    std::vector<double> b{std::istream_iterator<double>(bval), std::istream_iterator<double>()};
    ASSERT_EQ(b, (std::vector<double>{0, 500, 1000})) << "dcm2niix's volume order";
    for (std::uint32_t t = 0; t < 3; ++t) {
        SCOPED_TRACE(t);
        dicom::DicomSeriesSource ours(volumes[t]);
        core::NiftiVoxelSource theirs(nii("diffusion/7.nii"), t);
        expectSameVoxels(ours, theirs);
    }
}

TEST_F(PydicomSeries, TenTimePointsBecomeTenVolumes) {
    const auto volumes = import("dynamic");
    ASSERT_EQ(volumes.size(), 10u);
    for (std::uint32_t t = 0; t < 10; ++t) {
        SCOPED_TRACE(t);
        EXPECT_EQ(volumes[t].varying, "time " + std::to_string(t + 1));
        EXPECT_NE(volumes[t].label.find("time " + std::to_string(t + 1)), std::string::npos) << volumes[t].label;
        dicom::DicomSeriesSource ours(volumes[t]);
        core::NiftiVoxelSource theirs(nii("dynamic/7.nii"), t);
        expectSameVoxels(ours, theirs);
    }
}

TEST_F(PydicomSeries, ImagesNothingTellsApartAreRefusedNotMixed) {
    std::vector<std::string> notes;
    const auto volumes = import("twins", &notes);
    EXPECT_TRUE(volumes.empty()) << "a volume was made of images that share positions";
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("10 images share positions (within "), std::string::npos) << notes[0];
    EXPECT_NE(notes[0].find("mm) and nothing tells them apart"), std::string::npos) << notes[0];
    EXPECT_NE(notes[0].find("refused"), std::string::npos) << notes[0];
}

// Two acquisitions at the same positions whose every image has its own TriggerTime are two
// volumes, as dcm2niix's 4D image holds them (they had become ten one-slice volumes); two
// echoes numbered alike but of different TE are two echoes, as dcm2niix's e1 and e1a.
TEST_F(PydicomSeries, AcquisitionsToldApartByWhatSeparatesThemAll) {
    const auto gated = import("gated");
    ASSERT_EQ(gated.size(), 2u);
    for (std::uint32_t t = 0; t < 2; ++t) {
        SCOPED_TRACE(t);
        EXPECT_EQ(gated[t].varying, "acquisition " + std::to_string(t + 1));
        EXPECT_TRUE(gated[t].warnings.empty()) << gated[t].warnings.front();
        dicom::DicomSeriesSource ours(gated[t]);
        core::NiftiVoxelSource theirs(nii("gated/7.nii"), t);
        expectSameVoxels(ours, theirs);
    }
    const auto echoes = import("echo-te");
    ASSERT_EQ(echoes.size(), 2u);
    EXPECT_EQ(echoes[0].varying, "echo 1 (TE 10 ms)");
    EXPECT_EQ(echoes[1].varying, "echo 1 (TE 80 ms)");
    for (std::size_t e = 0; e < 2; ++e) {
        dicom::DicomSeriesSource ours(echoes[e]);
        core::NiftiVoxelSource theirs(nii(e == 0 ? "echo-te/7_e1.nii" : "echo-te/7_e1a.nii"));
        expectSameVoxels(ours, theirs);
    }
}

// Two acquisitions 0.3 mm apart are two evenly spaced volumes, never one interleaved stack
// interpolated between pre- and post-contrast (dcm2niix merges them, warning "Interslice
// distance varies"); images 2 um apart that nothing tells apart are refused (they had been
// resampled to thousands of slices); an image without a position is left out, not put at z = 2.
TEST_F(PydicomSeries, NearbyAcquisitionsStayApartAndUnplacedImagesAreLeftOut) {
    const auto offset = import("offset");
    ASSERT_EQ(offset.size(), 2u);
    for (std::size_t v = 0; v < 2; ++v) {
        SCOPED_TRACE(v);
        EXPECT_EQ(offset[v].varying, "acquisition " + std::to_string(v + 1));
        EXPECT_EQ(offset[v].geometry.dims[2], 5u);
        EXPECT_FALSE(offset[v].resample);
        EXPECT_TRUE(offset[v].warnings.empty()) << offset[v].warnings.front();
        dicom::DicomSeriesSource src(offset[v]);
        for (const double x : physical(src)) ASSERT_TRUE(x >= 1000.0 * double(v) && x < 1000.0 * double(v) + 1000.0) << x;
    }
    std::vector<std::string> notes;
    EXPECT_TRUE(import("near", &notes).empty());
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("10 images share positions (within 0.0"), std::string::npos) << notes[0];

    const auto unplaced = import("unplaced");
    ASSERT_EQ(unplaced.size(), 1u);
    EXPECT_TRUE(anyContains(unplaced[0].warnings, "1 image(s) without ImagePositionPatient (instance 3) left out"))
        << ::testing::PrintToString(unplaced[0].warnings);
    EXPECT_TRUE(anyContains(unplaced[0].warnings, "1 missing slice(s)")) << ::testing::PrintToString(unplaced[0].warnings);
    const auto& g = unplaced[0].geometry;
    EXPECT_EQ(g.dims[2], 5u);
    EXPECT_NEAR(glm::length(g.origin - glm::dvec3(-20.0, -15.0, 30.0)), 0.0, 1e-3) << "the stack starts at slice 0";
    EXPECT_NEAR(g.spacing.z, 2.5, 1e-3);
    // DTI with two b0 volumes told apart by their acquisition: named by b-value first.
    const auto dti = import("dti-two-b0");
    ASSERT_EQ(dti.size(), 4u);
    EXPECT_EQ(dti[0].varying, "b 0, acquisition 1");
    EXPECT_EQ(dti[1].varying, "b 0, acquisition 2");
    EXPECT_EQ(dti[2].varying.rfind("b 1000", 0), 0u) << dti[2].varying;
    // Odd and even slices of one grid, one lost: one volume with its gap said, not two halves.
    const auto interleaved = import("interleaved");
    ASSERT_EQ(interleaved.size(), 1u);
    EXPECT_EQ(interleaved[0].geometry.dims[2], 10u);
    EXPECT_TRUE(anyContains(interleaved[0].warnings, "1 missing slice(s)")) << ::testing::PrintToString(interleaved[0].warnings);
    // Without any position, two echoes are still two volumes, each in file order.
    const auto echoes = import("noplace-echo");
    ASSERT_EQ(echoes.size(), 2u);
    for (std::size_t v = 0; v < 2; ++v) {
        EXPECT_EQ(echoes[v].varying, "echo " + std::to_string(v + 1) + " (TE " + std::to_string(10 * (v + 1)) + " ms)");
        EXPECT_TRUE(anyContains(echoes[v].warnings, "no ImagePositionPatient: stacked in file order"));
        dicom::DicomSeriesSource src(echoes[v]);
        for (const double x : physical(src)) ASSERT_TRUE(x >= 1000.0 * double(v) && x < 1000.0 * double(v) + 1000.0) << x;
    }
}

// Rows and columns 80 degrees apart are a broken header: refused; 89.8 degrees apart, placed as
// stated with a warning naming the angle. Unsigned CT whose rescale cannot hold -1024 HU: the
// padding warning names the value padding takes (-1000 HU), which the voxels hold.
TEST_F(PydicomSeries, SkewedOrientationAndUnsignedPaddingAreNamed) {
    std::vector<std::string> notes;
    EXPECT_TRUE(import("skew", &notes).empty());
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("5 images whose ImageOrientationPatient is not two perpendicular directions"),
              std::string::npos) << notes[0];
    const auto small = import("skew-small");
    ASSERT_EQ(small.size(), 1u);
    EXPECT_TRUE(anyContains(small[0].warnings, "rows and columns are 89.80 degrees apart"))
        << ::testing::PrintToString(small[0].warnings);
    const auto pad = import("pad-unsigned");
    ASSERT_EQ(pad.size(), 1u);
    EXPECT_TRUE(anyContains(pad[0].warnings, "measured as -1000 HU (-1024 HU, air, lies below what the stored type holds"))
        << ::testing::PrintToString(pad[0].warnings);
    dicom::DicomSeriesSource src(pad[0]);
    const auto v = physical(src);
    for (std::size_t i = 0; i < 16; ++i) EXPECT_EQ(v[i], -1000.0) << "row 0 is padding";
    EXPECT_EQ(v[16], 100.0) << "row 1, column 0: 1100 - 1000";
}

// A dual-energy iodine map (RescaleType MGML) is a CT whose values are not HU: the import says
// so, padding takes the lowest stored value, not -1024 "HU", and measure prints no HU, also
// from the octree built from it.
TEST_F(PydicomSeries, CtValuesNotInHounsfieldUnitsAreNotCalledHu) {
    const auto volumes = import("iodine");
    ASSERT_EQ(volumes.size(), 1u);
    const auto& g = volumes[0].geometry;
    EXPECT_EQ(g.modality, "CT");
    EXPECT_FALSE(g.hounsfield());
    EXPECT_TRUE(anyContains(volumes[0].warnings, "values in MGML (RescaleType), not Hounsfield units"))
        << ::testing::PrintToString(volumes[0].warnings);
    EXPECT_TRUE(anyContains(volumes[0].warnings, "measured as -32.768, the lowest value the stored bits hold"))
        << ::testing::PrintToString(volumes[0].warnings);
    const std::string db = " --db " + dir_->file("iodine.sqlite");
    auto r = test::runCommand(std::string(HVX_CLI) + " import " + dir_->file("dcm/iodine") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(std::string(HVX_CLI) + " build-series " + volumes[0].seriesUid + " -o " + dir_->file("iodine.hvo") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_FALSE(core::OctreeReader::open(dir_->file("iodine.hvo"))->geometry().hounsfield());
    r = test::runCommand(std::string(HVX_CLI) + " measure " + dir_->file("iodine.hvo") + " --roi box:-100,-100,-100,100,100,100");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("HU"), std::string::npos) << r.output;
    EXPECT_TRUE(std::regex_search(r.output, std::regex("max +7 *\n"))) << r.output;
    EXPECT_TRUE(std::regex_search(r.output, std::regex("min +-32.768 *\n"))) << r.output;
}

// Names in Latin-1, Cyrillic and GB18030 (SpecificCharacterSet) are read as UTF-8, as pydicom
// wrote them (Latin-1 bytes had been stored as they were, invalid UTF-8).
TEST_F(PydicomSeries, NamesInOtherCharacterSetsAreReadAsUtf8) {
    const std::vector<std::pair<std::string, std::string>> want = {
        {"IM0", "M\u00fcller^J\u00fcrgen"}, {"IM1", "\u0418\u0432\u0430\u043d\u043e\u0432^\u0418\u0432\u0430\u043d"},
        {"IM2", "\u738b^\u5c0f\u660e"}};
    for (const auto& [file, name] : want) {
        dicom::DicomInstance in;
        ASSERT_EQ(dicom::DicomHeaderReader::read(dir_->file("dcm/charsets/" + file), in), dicom::DicomHeaderReader::Kind::Dicom);
        EXPECT_EQ(in.patientName, name) << file;
        EXPECT_EQ(in.studyDescription, name.substr(0, name.find('^'))) << file;
    }
}

// pydicom's own character-set files (Debian's python3-pydicom ships them), each patient name read
// as pydicom reads it: Japanese code extensions (ISO 2022 IR 13 and 87, which DCMTK's iconv
// conversion refuses), Korean (IR 149), GB18030, Arabic, Greek, Hebrew, Cyrillic and Latin-1.
// Empty trailing component groups ("Wang^XiaoDong=王^小東=") are not compared: pydicom drops them.
TEST_F(PydicomSeries, PydicomsCharacterSetFilesAreReadAsPydicomReadsThem) {
    const auto r = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) + "/tests/support/charset_names.py");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    auto trimmed = [](std::string name) {
        while (!name.empty() && (name.back() == '=' || name.back() == '^')) name.pop_back();
        return name;
    };
    std::istringstream lines(r.output);
    int compared = 0, japanese = 0;
    for (std::string line; std::getline(lines, line);) {
        const auto tab = line.find('\t');
        ASSERT_NE(tab, std::string::npos) << line;
        const std::string path = line.substr(0, tab), name = line.substr(tab + 1);
        dicom::DicomInstance in;
        ASSERT_EQ(dicom::DicomHeaderReader::read(path, in), dicom::DicomHeaderReader::Kind::Dicom) << path;
        EXPECT_EQ(trimmed(in.patientName), trimmed(name)) << path;
        ++compared;
        japanese += name.find("\u3084\u307e\u3060") != std::string::npos;  // やまだ
    }
    EXPECT_GE(compared, 15);
    EXPECT_GE(japanese, 4);
}

// A series imported in two halves (two folders, two retrieves) is recorded whole the second
// time, its volumes and warnings the whole series' (the first half's gaps had stayed), even when
// a file of the first half is gone by then; `import` lists the whole series.
TEST_F(PydicomSeries, ASeriesImportedInTwoHalvesIsRecordedWhole) {
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(dir_->file("dcm/echo"))) files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    ASSERT_EQ(files.size(), 24u);
    test::TempDir halves;
    std::filesystem::create_directories(halves.file("a"));
    std::filesystem::create_directories(halves.file("b"));
    for (std::size_t i = 0; i < files.size(); ++i)
        std::filesystem::copy_file(files[i], halves.file((i < 12 ? "a/" : "b/") + std::to_string(i)));
    const std::string db = " --db " + halves.file("db.sqlite");
    auto r = test::runCommand(std::string(HVX_CLI) + " import " + halves.file("a") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::filesystem::remove(halves.file("a/0"));  // gone before the second half comes
    r = test::runCommand(std::string(HVX_CLI) + " import " + halves.file("b") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("echo 1 (TE 10 ms)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("echo 2 (TE 20 ms)"), std::string::npos) << r.output;
    dicom::StudyDatabase database(halves.file("db.sqlite"));
    const auto volumes = import("echo");
    const auto rows = database.volumesOfSeries(volumes[0].seriesUid);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].varying, "echo 1 (TE 10 ms)");
    EXPECT_EQ(rows[1].varying, "echo 2 (TE 20 ms)");
}

TEST_F(PydicomSeries, CliListsEachVolumeAndBuildsTheOneAsked) {
    const std::string db = " --db " + dir_->file("db.sqlite");
    auto r = test::runCommand(std::string(HVX_CLI) + " import " + dir_->file("dcm/echo") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("#1 MR #7 \u2014 echo 1 (TE 10 ms)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("#2 MR #7 \u2014 echo 2 (TE 20 ms)"), std::string::npos) << r.output;
    const auto volumes = import("echo");
    r = test::runCommand(std::string(HVX_CLI) + " build-series " + volumes[1].seriesUid + " --volume 2 -o " +
                         dir_->file("e2.hvo") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("echo 2 (TE 20 ms)"), std::string::npos) << r.output;
    // The study database knows the series' volumes and what varies between them.
    r = test::runCommand(std::string(HVX_CLI) + " studies" + db);
    EXPECT_NE(r.output.find("#1 echo 1 (TE 10 ms)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("#2 echo 2 (TE 20 ms)"), std::string::npos) << r.output;
    dicom::StudyDatabase database(dir_->file("db.sqlite"));
    const auto rows = database.volumesOfSeries(volumes[1].seriesUid);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[1].varying, "echo 2 (TE 20 ms)");
    // Building volume 2 records its octree; importing again keeps it; a changed split drops it.
    core::JobContext job;
    const auto path = dicom::SeriesOctree::build(database, volumes[1].seriesUid, job, nullptr, {}, 2);
    EXPECT_EQ(database.volumesOfSeries(volumes[1].seriesUid)[1].octreePath, path);
    database.setSeriesVolumes(volumes[1].seriesUid, {"echo 1 (TE 10 ms)", "echo 2 (TE 20 ms)"});
    EXPECT_EQ(database.volumesOfSeries(volumes[1].seriesUid)[1].octreePath, path);
    database.setSeriesVolumes(volumes[1].seriesUid, {"echo 1 (TE 10 ms)"});
    EXPECT_EQ(database.volumesOfSeries(volumes[1].seriesUid).size(), 1u);
}

TEST_F(PydicomSeries, SliceOffTheStackLineIsNamed) {
    const auto volumes = import("offline");
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_TRUE(anyContains(volumes[0].warnings, "off the stack's line by up to 2 mm (instances 4)"))
        << ::testing::PrintToString(volumes[0].warnings);
    const auto plain = import("echo");
    EXPECT_FALSE(anyContains(plain[0].warnings, "off the stack's line"));
}

TEST_F(PydicomSeries, MissingSpacingAndOrientationAreNamed) {
    const auto volumes = import("nogeometry");
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_TRUE(anyContains(volumes[0].warnings, "spacing unknown, assumed 1 mm")) << ::testing::PrintToString(volumes[0].warnings);
    EXPECT_TRUE(anyContains(volumes[0].warnings, "orientation unknown")) << ::testing::PrintToString(volumes[0].warnings);
    // Its positions run off the assumed normal: said as such, not as a gantry tilt.
    EXPECT_FALSE(anyContains(volumes[0].warnings, "gantry tilt of")) << ::testing::PrintToString(volumes[0].warnings);
    EXPECT_TRUE(anyContains(volumes[0].warnings, "off the assumed slice normal"))
        << ::testing::PrintToString(volumes[0].warnings);
    // The assumption travels with the volume: into its octree (the views say it and draw "?"
    // for the orientation letters), into the study database (the browser row and `studies`),
    // and an export refuses to write it down as a fact.
    EXPECT_TRUE(volumes[0].geometry.spacingAssumed);
    EXPECT_TRUE(volumes[0].geometry.orientationAssumed);
    const std::string db = " --db " + dir_->file("nogeometry.sqlite");
    auto r = test::runCommand(std::string(HVX_CLI) + " import " + dir_->file("dcm/nogeometry") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(std::string(HVX_CLI) + " studies" + db);
    EXPECT_NE(r.output.find("warning: spacing unknown, assumed 1 mm (no PixelSpacing)"), std::string::npos)
        << r.output;
    dicom::StudyDatabase database(dir_->file("nogeometry.sqlite"));
    dicom::SeriesRow row;
    ASSERT_TRUE(database.findSeries(volumes[0].seriesUid, row));
    EXPECT_TRUE(anyContains(row.warnings, "orientation unknown")) << ::testing::PrintToString(row.warnings);
    core::JobContext job;
    const auto path = dicom::SeriesOctree::build(database, volumes[0].seriesUid, job);
    const auto reader = core::OctreeReader::open(path);
    EXPECT_TRUE(reader->geometry().spacingAssumed);
    EXPECT_TRUE(reader->geometry().orientationAssumed);
    r = test::runCommand(std::string(HVX_CLI) + " export-dicom --series-uid " + volumes[0].seriesUid + db + " -o " +
                         dir_->file("nogeometry-export"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("an export would write the assumption as a fact"), std::string::npos) << r.output;
    // A series with its geometry has no warning in its row.
    ASSERT_EQ(test::runCommand(std::string(HVX_CLI) + " import " + dir_->file("dcm/echo") + db).exitCode, 0);
    ASSERT_TRUE(database.findSeries(import("echo")[0].seriesUid, row));
    EXPECT_TRUE(row.warnings.empty()) << ::testing::PrintToString(row.warnings);
}

// Nine frames of one object, interleaved axial, coronal and sagittal: three stacks, each along
// its own normal (taking frame 0's normal for all collapsed two of them onto one position).
TEST_F(PydicomSeries, ThreePlaneEnhancedLocalizerBecomesThreeStacks) {
    const auto volumes = import("localizer");
    ASSERT_EQ(volumes.size(), 3u);
    struct Expect {
        glm::dvec3 k, origin;
        double firstValue;
    };
    // Sorted along each normal: axial z 5, 9, 13 (frames 0, 3, 6); coronal (normal +y) y 3, 7, 11
    // (frames 1, 4, 7); sagittal (normal -x) x 10, 6, 2 (frames 8, 5, 2).
    const Expect expect[3] = {{{0, 0, 1}, {-10, -8, 5}, 0}, {{0, 1, 0}, {-10, 3, 20}, 1000}, {{-1, 0, 0}, {10, -8, 20}, 8000}};
    int found = 0;
    for (const auto& v : volumes) {
        EXPECT_EQ(v.geometry.dims[2], 3u);
        for (const auto& e : expect) {
            if (glm::length(v.geometry.direction[2] - e.k) > 1e-9) continue;
            ++found;
            EXPECT_NEAR(glm::length(v.geometry.origin - e.origin), 0.0, 1e-6) << v.label;
            EXPECT_NEAR(v.geometry.spacing.z, 4.0, 1e-9);
            dicom::DicomSeriesSource src(v);
            EXPECT_EQ(physical(src)[0], e.firstValue) << v.label;
        }
    }
    EXPECT_EQ(found, 3);
}

TEST_F(PydicomSeries, SingleFrameEnhancedUsesItsPerFrameGroups) {
    const auto volumes = import("enhanced1");
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_EQ(volumes[0].geometry.origin, glm::dvec3(11.5, -7.25, 42.0));
    dicom::DicomSeriesSource src(volumes[0]);
    EXPECT_EQ(physical(src)[5], 2.0 * 5 - 100) << "stored 5 at column 5, slope 2, intercept -100";
}

TEST_F(PydicomSeries, RtDoseAbsoluteOffsetsAndSinglePlaneScaling) {
    const auto volumes = import("dose");
    ASSERT_EQ(volumes.size(), 1u);
    const auto& g = volumes[0].geometry;
    EXPECT_EQ(g.dims[2], 3u);
    EXPECT_NEAR(glm::length(g.origin - glm::dvec3(-10, -8, -40)), 0.0, 1e-9) << "absolute offsets taken as relative";
    EXPECT_NEAR(g.spacing.z, 3.0, 1e-9);
    dicom::DicomSeriesSource src(volumes[0]);
    const auto v = physical(src);
    EXPECT_NEAR(v[0], 1.0, 1e-9);
    EXPECT_NEAR(v[std::size_t(2) * 12 * 16 + 3], 3.003, 1e-9);
    const auto single = import("dose1");
    ASSERT_EQ(single.size(), 1u);
    dicom::DicomSeriesSource one(single[0]);
    EXPECT_NEAR(physical(one)[7], 1.007, 1e-9) << "DoseGridScaling of a single plane";
}

TEST_F(PydicomSeries, UnsignedThirtyTwoBitPixelsNeverWrapNegative) {
    const auto volumes = import("uint32");
    ASSERT_EQ(volumes.size(), 1u);
    dicom::DicomSeriesSource src(volumes[0]);
    const auto v = physical(src);
    for (std::size_t i = 0; i < v.size(); ++i) {
        const double expected = 2147483648.0 + 1000.0 * double(i / (12 * 16)) + double(i % 16);
        ASSERT_NEAR(v[i], expected, 256.0) << "voxel " << i << " (float32 keeps 24 bits)";
    }
}

TEST_F(PydicomSeries, DicomWindowsAreTheVolumesOwn) {
    const auto volumes = import("windows");
    ASSERT_EQ(volumes.size(), 1u);
    const auto& w = volumes[0].geometry.windows;
    ASSERT_EQ(w.size(), 2u);
    EXPECT_EQ(w[0].name, "SOFT TISSUE");
    EXPECT_DOUBLE_EQ(w[0].centre, 40);
    EXPECT_DOUBLE_EQ(w[0].width, 400);
    EXPECT_EQ(w[1].name, "BONE");
    EXPECT_DOUBLE_EQ(w[1].centre, 300);
    EXPECT_DOUBLE_EQ(w[1].width, 1500);
    EXPECT_TRUE(import("echo")[0].geometry.windows.empty());
}

TEST_F(PydicomSeries, FloatPixelsThatAreNotNumbersOrBeyondFloat32AreRefusedNamingTheFile) {
    for (const auto& [name, file, said] :
         {std::tuple<std::string, std::string, std::string>{"float-nan", "IM1", "its pixels hold 2 NaN (not-a-number) values"},
          {"double-huge", "IM2", "its pixels hold 2 values beyond what a 32-bit float can hold"}}) {
        SCOPED_TRACE(name);
        const auto volumes = import(name);
        ASSERT_EQ(volumes.size(), 1u);
        dicom::DicomSeriesSource src(volumes[0]);
        std::string e;
        try {
            physical(src);
        } catch (const core::Error& x) {
            e = x.what();
        }
        EXPECT_NE(e.find(file + ": " + said), std::string::npos) << e;
    }
}

TEST_F(PydicomSeries, NmMultiFrameIsRefusedNotStackedInFileOrder) {
    std::vector<std::string> notes;
    const auto volumes = import("nm", &notes);
    EXPECT_TRUE(volumes.empty());
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("NM multi-frame objects"), std::string::npos) << notes[0];
}

TEST_F(PydicomSeries, FloatAndDoubleFloatPixelDataAreImported) {
    for (const std::string name : {"float", "double"}) {
        SCOPED_TRACE(name);
        const auto volumes = import(name);
        ASSERT_EQ(volumes.size(), 1u);
        EXPECT_EQ(volumes[0].geometry.scalarType, core::ScalarType::Float32);
        dicom::DicomSeriesSource src(volumes[0]);
        const auto v = physical(src);
        ASSERT_EQ(v.size(), std::size_t(16 * 12 * 3));
        for (std::size_t i = 0; i < v.size(); ++i) {
            const double c = double(i % 16), r = double((i / 16) % 12), s = double(i / (16 * 12));
            ASSERT_NEAR(v[i], 0.125 * c - 0.5 * r + 1000.25 * s - 3.75, 1e-4) << "voxel " << i;
        }
    }
}

// CT padding (-2000, outside the scanned field) becomes -1024 HU on every slice: beside a
// rescale that differs between slices (it had been converted with each slice's own rescale:
// -512 HU), across a Pixel Padding Range Limit (-1600 had stayed a measurement), and when the
// padding value is written US beside signed pixels (63536 is -2000's bits; it had never matched).
TEST_F(PydicomSeries, PaddingIsAirOnEverySliceWhateverItsRescaleOrEncoding) {
    for (const std::string name : {"pad-rescale", "pad-range", "pad-us"}) {
        SCOPED_TRACE(name);
        const auto volumes = import(name);
        ASSERT_EQ(volumes.size(), 1u);
        EXPECT_TRUE(anyContains(volumes[0].warnings, "padding (outside the scanned field) are shown and measured as -1024 HU"))
            << ::testing::PrintToString(volumes[0].warnings);
        dicom::DicomSeriesSource src(volumes[0]);
        const auto& g = src.geometry();
        const auto v = physical(src);
        ASSERT_EQ(v.size(), std::size_t(4 * 12 * 16));
        for (std::uint32_t k = 0; k < 4; ++k)
            for (std::uint32_t j = 0; j < g.dims[1]; ++j)
                for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
                    const bool padding = j == 0 || (name == "pad-range" && j == 1);
                    const double want = padding ? -1024.0 : 100.0 + 2.0 * i;
                    ASSERT_NEAR(v[(std::size_t(k) * g.dims[1] + j) * g.dims[0] + i], want, 1e-3)
                        << "slice " << k << ", row " << j << ", column " << i;
                }
    }
}

// A decimal comma in a DS value ("-20,5"), which DCMTK reads as -20 without a word, refuses
// the file naming the element; PALETTE COLOR pixels (table indices) are not stacked as values;
// orientations 2e-6 apart are one stack (they had been split into interleaved halves).
TEST_F(PydicomSeries, MalformedNumbersPaletteColourAndOrientationNoise) {
    core::JobContext job;
    const auto comma = dicom::DicomScanner::scan({dir_->file("dcm/decimal-comma")}, job);
    EXPECT_TRUE(comma.instances.empty());
    EXPECT_EQ(comma.broken, 3u);
    ASSERT_FALSE(comma.brokenReasons.empty());
    EXPECT_NE(comma.brokenReasons[0].find("ImagePositionPatient '-20,5\\-15\\"), std::string::npos) << comma.brokenReasons[0];
    EXPECT_NE(comma.brokenReasons[0].find("a decimal comma"), std::string::npos) << comma.brokenReasons[0];
    std::vector<std::string> notes;
    EXPECT_TRUE(import("palette", &notes).empty());
    EXPECT_TRUE(anyContains(notes, "3 images of photometric interpretation PALETTE COLOR")) << ::testing::PrintToString(notes);
    const auto jitter = import("iop-jitter", &notes);
    ASSERT_EQ(jitter.size(), 1u) << ::testing::PrintToString(notes);
    EXPECT_EQ(jitter[0].geometry.dims[2], 8u);
    EXPECT_NEAR(jitter[0].geometry.spacing.z, 2.5, 1e-3);
}
