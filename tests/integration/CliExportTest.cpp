// export-dicom checked by an independent validator, dicom3tools' dciodvfy (no "Error" line for
// CT, MR and Secondary Capture exports, and the Legacy Converted Enhanced CT and MR objects of
// --enhanced), and float volumes exported as 16-bit with a rescale:
// read back, every value within the largest error the command reports, itself within half a
// step of the 16-bit scale.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/base/JobContext.h"
#include "dicom/DicomScanner.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/SeriesAssembler.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string cli = HVX_CLI;

std::size_t errorLines(const std::string& file) {
    const auto r = test::runCommand("dciodvfy " + file + " 2>&1");
    std::istringstream in(r.output);
    std::size_t n = 0;
    for (std::string line; std::getline(in, line);) n += line.rfind("Error", 0) == 0;
    return n;
}
}  // namespace

TEST(CliExport, EveryModalityPassesDciodvfy) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand(cli + " phantom --size 32x24x6 -o " + dir.file("p.nrrd")).exitCode, 0);
    ASSERT_EQ(test::runCommand("command -v dciodvfy").exitCode, 0) << "dicom3tools (installer/install-deps.sh)";
    for (const std::string m : {"CT", "MR", "PT", "OT"}) {
        const auto r = test::runCommand(cli + " export-dicom " + dir.file("p.nrrd") + " --modality " + m + " -o " +
                                        dir.file("out-" + m));
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const std::string first = dir.file("out-" + m + "/IMG00001.dcm");
        EXPECT_EQ(errorLines(first), 0u) << m << ":\n" << test::runCommand("dciodvfy " + first + " 2>&1").output;
        const auto iod = test::runCommand("dciodvfy " + first + " 2>&1").output;
        const char* expected = m == "CT" ? "CTImage" : m == "MR" ? "MRImage" : "SCImage";
        EXPECT_NE(iod.find(expected), std::string::npos) << m << " written as " << iod.substr(0, 40);
    }
    // --enhanced: one Legacy Converted Enhanced CT or MR object, also free of dciodvfy errors.
    for (const std::string m : {"CT", "MR"}) {
        const auto r = test::runCommand(cli + " export-dicom " + dir.file("p.nrrd") + " --enhanced --modality " + m +
                                        " -o " + dir.file("enh-" + m));
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const std::string file = dir.file("enh-" + m + "/ENHANCED.dcm");
        const auto report = test::runCommand("dciodvfy " + file + " 2>&1").output;
        EXPECT_EQ(errorLines(file), 0u) << m << " enhanced:\n" << report;
        EXPECT_NE(report.find("LegacyConvertedEnhanced" + m + "Image"), std::string::npos) << report.substr(0, 60);
        // pydicom, independently: frame k is single-frame image k, in pixels and position.
        const std::string script =
            "import pydicom,glob,sys,numpy as np\n"
            "e=pydicom.dcmread(sys.argv[1]); a=e.pixel_array\n"
            "s=[pydicom.dcmread(f) for f in sorted(glob.glob(sys.argv[2]+'/IMG*.dcm'))]\n"
            "assert len(s)==e.NumberOfFrames==a.shape[0], (len(s), e.NumberOfFrames)\n"
            "for k,f in enumerate(s):\n"
            "  p=e.PerFrameFunctionalGroupsSequence[k].PlanePositionSequence[0].ImagePositionPatient\n"
            "  assert np.array_equal(a[k], f.pixel_array), k\n"
            "  assert np.allclose([float(x) for x in p], [float(x) for x in f.ImagePositionPatient]), k\n"
            "print('frames match', len(s))\n";
        std::ofstream(dir.file("frames.py")) << script;
        const auto py = test::runCommand("/usr/bin/python3 " + dir.file("frames.py") + " " + file + " " +
                                         dir.file("out-" + m) + " 2>&1");
        EXPECT_EQ(py.exitCode, 0) << py.output;
    }
    const auto r = test::runCommand(cli + " export-dicom " + dir.file("p.nrrd") + " --modality PT --enhanced -o " +
                                    dir.file("out-enh"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("is written as single-frame images"), std::string::npos) << r.output;
}

// Names beyond ASCII are written in the character set the files name (UTF-8, ISO_IR 192), and
// pydicom reads them back as given; declared Latin-1, "Müller" had read as "MÃ¼ller".
TEST(CliExport, NamesBeyondAsciiAreWrittenInTheCharacterSetTheFilesName) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand(cli + " phantom --size 16x16x3 -o " + dir.file("p.nrrd")).exitCode, 0);
    const std::string name = "M\u00fcller^J\u00fcrgen=\u5c71\u7530^\u592a\u90ce", study = "\u00c9tude \u00e0 l'\u00e9cole";
    auto r = test::runCommand(cli + " export-dicom " + dir.file("p.nrrd") + " --modality CT --patient '" + name +
                              "' --patient-id P1 --study \"" + study + "\" -o " + dir.file("out"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ofstream(dir.file("names.py")) << "import pydicom, sys\n"
                                           "d = pydicom.dcmread(sys.argv[1])\n"
                                           "print(d.SpecificCharacterSet)\n"
                                           "print(str(d.PatientName))\n"
                                           "print(d.StudyDescription)\n";
    r = test::runCommand("/usr/bin/python3 " + dir.file("names.py") + " " + dir.file("out/IMG00001.dcm"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output, "ISO_IR 192\n" + name + "\n" + study + "\n");
    EXPECT_EQ(errorLines(dir.file("out/IMG00001.dcm")), 0u) << test::runCommand("dciodvfy " + dir.file("out/IMG00001.dcm") + " 2>&1").output;
}

TEST(CliExport, FloatVolumeIsWrittenAsSixteenBitWithinTheReportedError) {
    test::TempDir dir;
    const int nx = 20, ny = 16, nz = 5;
    std::vector<float> values;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) values.push_back(float(std::sin(0.3 * i + 0.7 * j) * 123.456 + k * 10.25 - 3.5));
    {
        std::ofstream f(dir.file("f.nrrd"), std::ios::binary);
        f << "NRRD0004\ntype: float\ndimension: 3\nsizes: " << nx << " " << ny << " " << nz
          << "\nspace: left-posterior-superior\nspace directions: (0.5,0,0) (0,0.5,0) (0,0,2)\nspace origin: (0,0,0)\n"
             "endian: little\nencoding: raw\nmodality:=MR\n\n";
        f.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
    }
    const auto r = test::runCommand(cli + " export-dicom " + dir.file("f.nrrd") + " -o " + dir.file("out"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    double slope = 0, intercept = 0, reported = 0;
    const auto at = r.output.find("slope ");
    ASSERT_NE(at, std::string::npos) << r.output;
    ASSERT_EQ(std::sscanf(r.output.c_str() + at, "slope %lf and intercept %lf: largest error %lf", &slope, &intercept,
                          &reported),
              3)
        << r.output;
    EXPECT_LE(reported, slope / 2 * 1.0001) << "within half a step";
    EXPECT_EQ(errorLines(dir.file("out/IMG00001.dcm")), 0u);
    core::JobContext job;
    const auto scan = dicom::DicomScanner::scan({dir.file("out")}, job);
    std::vector<std::string> notes;
    auto volumes = dicom::SeriesAssembler::assemble(scan.instances, notes);
    ASSERT_EQ(volumes.size(), 1u);
    dicom::DicomSeriesSource src(volumes[0]);
    const auto& g = src.geometry();
    ASSERT_EQ(g.voxelCount(), values.size());
    std::vector<std::int16_t> stored(values.size());
    ASSERT_EQ(g.scalarType, core::ScalarType::Int16);
    src.readSlices(0, g.dims[2], stored.data());
    double worst = 0;
    for (std::size_t i = 0; i < values.size(); ++i)
        worst = std::max(worst, std::abs(stored[i] * g.rescaleSlope + g.rescaleIntercept - double(values[i])));
    EXPECT_LE(worst, reported * 1.0001 + 1e-6) << "read back through Holovox's DICOM import";
}

// Exporting an imported series keeps who and where it is: the same patient, study and frame
// of reference (so the export registers with its source), under a series of its own.
TEST(CliExport, ASeriesKeepsItsPatientStudyAndFrameOfReference) {
    test::TempDir dir;
    auto r = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) + "/tests/support/dicom_cases.py " +
                              dir.file("cases"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string db = " --db " + dir.file("db.sqlite");
    r = test::runCommand(cli + " import " + dir.file("cases/echo") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    core::JobContext job;
    const auto scan = dicom::DicomScanner::scan({dir.file("cases/echo")}, job);
    const auto& source = scan.instances.front();
    ASSERT_FALSE(source.frameOfReferenceUid.empty());
    r = test::runCommand(cli + " export-dicom --series-uid " + source.seriesInstanceUid + " --volume 2" + db + " -o " +
                         dir.file("out"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto back = dicom::DicomScanner::scan({dir.file("out")}, job);
    ASSERT_EQ(back.instances.size(), 12u);
    for (const auto& in : back.instances) {
        EXPECT_EQ(in.patientId, source.patientId);
        EXPECT_EQ(in.patientName, source.patientName);
        EXPECT_EQ(in.studyInstanceUid, source.studyInstanceUid);
        EXPECT_EQ(in.frameOfReferenceUid, source.frameOfReferenceUid);
        EXPECT_NE(in.seriesInstanceUid, source.seriesInstanceUid);
        EXPECT_EQ(in.modality, "MR");
    }
    EXPECT_EQ(errorLines(dir.file("out/IMG00001.dcm")), 0u);
    // What the stacking did is said and written into each image: the 4th slice of `offline`
    // lies 2 mm off the stack's line and was placed by its position along it.
    r = test::runCommand(cli + " import " + dir.file("cases/offline") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto offline = dicom::DicomScanner::scan({dir.file("cases/offline")}, job);
    r = test::runCommand(cli + " export-dicom --series-uid " + offline.instances.front().seriesInstanceUid + db + " -o " +
                         dir.file("off"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("off the stack's line"), std::string::npos) << r.output;
    const auto dump = test::runCommand("dcmdump +L +P DerivationDescription " + dir.file("off/IMG00003.dcm") + " 2>&1");
    EXPECT_NE(dump.output.find("off the stack's line"), std::string::npos) << dump.output;
}

// A 4-D file exports the volume asked for (--volume had been accepted and ignored: volume 1
// was written whatever N), and says which of how many it is.
TEST(CliExport, AFourDimensionalFileExportsTheVolumeAsked) {
    test::TempDir dir;
    const int nx = 6, ny = 5, nz = 4, volumes = 3;
    std::vector<std::int16_t> values;
    for (int v = 0; v < volumes; ++v)
        for (int i = 0; i < nx * ny * nz; ++i) values.push_back(std::int16_t(1000 * v + i));
    {
        std::ofstream f(dir.file("seq.nrrd"), std::ios::binary);
        f << "NRRD0004\ntype: int16\ndimension: 4\nsizes: " << nx << " " << ny << " " << nz << " " << volumes
          << "\nkinds: domain domain domain list\nspace: left-posterior-superior\n"
             "space directions: (1,0,0) (0,1,0) (0,0,2) none\nspace origin: (0,0,0)\nendian: little\nencoding: raw\n\n";
        f.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(std::int16_t)));
    }
    const auto r = test::runCommand(cli + " export-dicom " + dir.file("seq.nrrd") + " --volume 3 --modality MR -o " +
                                    dir.file("out") + " 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("a 4D file of 3 volumes; this is volume 3"), std::string::npos) << r.output;
    core::JobContext job;
    const auto scan = dicom::DicomScanner::scan({dir.file("out")}, job);
    std::vector<std::string> notes;
    auto back = dicom::SeriesAssembler::assemble(scan.instances, notes);
    ASSERT_EQ(back.size(), 1u);
    dicom::DicomSeriesSource src(back[0]);
    const auto& g = src.geometry();
    ASSERT_EQ(g.voxelCount(), std::uint64_t(nx * ny * nz));
    std::vector<std::int16_t> stored(g.voxelCount());
    ASSERT_EQ(g.scalarType, core::ScalarType::Int16);
    src.readSlices(0, g.dims[2], stored.data());
    for (std::size_t i = 0; i < stored.size(); ++i)
        ASSERT_EQ(stored[i] * g.rescaleSlope + g.rescaleIntercept, 2000.0 + double(i)) << "voxel " << i;
    const auto past = test::runCommand(cli + " export-dicom " + dir.file("seq.nrrd") + " --volume 4 -o " +
                                       dir.file("none") + " 2>&1");
    EXPECT_NE(past.exitCode, 0);
    EXPECT_NE(past.output.find("holds 3 volumes; there is no volume 4"), std::string::npos) << past.output;
}

// What an export must never do: mix with or replace files already in its folder, leave half a
// series behind when it fails, write an orientation DICOM cannot state, coarsen a CT's HU by
// an outlier, make up a patient, or write 8-bit CT/MR (their IODs hold 16 bits).
TEST(CliExport, AnExportNeverMixesFilesLeavesHalfASeriesOrMakesThingsUp) {
    test::TempDir dir;
    const std::string script =
        "import gzip, sys, numpy as np\n"
        "def nrrd(path, a, kind, dirs='(1,0,0) (0,1,0) (0,0,2)', enc='raw', cut=False):\n"
        "    h = ('NRRD0004\\ntype: %s\\ndimension: 3\\nsizes: %d %d %d\\nspace: left-posterior-superior\\n'\n"
        "         'space directions: %s\\nencoding: %s\\nendian: little\\n\\n') % (kind, a.shape[2], a.shape[1], a.shape[0], dirs, enc)\n"
        "    data = a.tobytes() if enc == 'raw' else gzip.compress(a.tobytes())\n"
        "    open(path, 'wb').write(h.encode() + (data[:len(data) // 2] if cut else data))\n"
        "rng = np.random.default_rng(3)\n"
        "out = sys.argv[1]\n"
        "nrrd(out + '/u8.nrrd', rng.integers(0, 256, (5, 24, 32), dtype=np.uint8), 'uchar')\n"
        "nrrd(out + '/cut.nrrd', rng.integers(-1000, 3000, (40, 64, 64), dtype=np.int16), 'short', enc='gzip', cut=True)\n"
        "nrrd(out + '/shear.nrrd', np.zeros((4, 24, 32), np.int16), 'short', dirs='(1,0,0) (0.3,1,0) (0,0,2)')\n"
        "f = rng.uniform(-1000, 3000, (4, 24, 32)).astype(np.float32); f[2, 5, 5] = 3e8\n"
        "nrrd(out + '/outlier.nrrd', f, 'float')\n";
    std::ofstream(dir.file("make.py")) << script;
    auto r = test::runCommand("/usr/bin/python3 " + dir.file("make.py") + " " + dir.path().string() + " 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    auto files = [&](const std::string& folder) {
        std::size_t n = 0;
        for (const auto& e : std::filesystem::directory_iterator(dir.file(folder))) n += e.is_regular_file();
        return n;
    };
    // 8-bit as CT: widened to 16 bits, free of dciodvfy errors, the values as they were; no
    // patient given: the name and ID are left empty, and the command says so.
    r = test::runCommand(cli + " export-dicom " + dir.file("u8.nrrd") + " --modality CT -o " + dir.file("u8") + "/");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("the patient's name and ID are left empty"), std::string::npos) << r.output;
    EXPECT_EQ(errorLines(dir.file("u8/IMG00001.dcm")), 0u) << test::runCommand("dciodvfy " + dir.file("u8/IMG00001.dcm") + " 2>&1").output;
    const std::string check =
        "import pydicom, glob, sys, numpy as np\n"
        "s = sorted((pydicom.dcmread(f) for f in glob.glob(sys.argv[1] + '/IMG*.dcm')), key=lambda d: d.InstanceNumber)\n"
        "a = np.stack([d.pixel_array for d in s])\n"
        "raw = np.fromfile(sys.argv[2], np.uint8)[-a.size:].reshape(a.shape)\n"
        "assert s[0].BitsAllocated == 16, s[0].BitsAllocated\n"
        "assert np.array_equal(a, raw)\n"
        "assert str(s[0].PatientName) == '' and s[0].PatientID == '', (s[0].PatientName, s[0].PatientID)\n"
        "print('ok')\n";
    std::ofstream(dir.file("check.py")) << check;
    r = test::runCommand("/usr/bin/python3 " + dir.file("check.py") + " " + dir.file("u8") + " " + dir.file("u8.nrrd") + " 2>&1");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    // Into a folder that holds files: refused, and the files stay as they were.
    r = test::runCommand(cli + " export-dicom " + dir.file("u8.nrrd") + " --patient OTHER -o " + dir.file("u8"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("already holds files"), std::string::npos) << r.output;
    EXPECT_EQ(files("u8"), 5u);
    // A source that fails half way (gzip data cut short): nothing left, neither the folder nor
    // the one beside it the series was written into.
    r = test::runCommand(cli + " export-dicom " + dir.file("cut.nrrd") + " --patient P -o " + dir.file("cut"));
    EXPECT_NE(r.exitCode, 0);
    std::size_t left = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        left += e.path().filename().string().rfind("cut", 0) == 0 && e.path().extension() != ".nrrd";
    EXPECT_EQ(left, 0u) << r.output;
    // Into an empty folder that exists (a mount point, "."): written into it, and on failure
    // what was written is removed and the folder stays, empty.
    std::filesystem::create_directory(dir.file("empty"));
    r = test::runCommand(cli + " export-dicom " + dir.file("cut.nrrd") + " --patient P -o " + dir.file("empty"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_TRUE(std::filesystem::is_directory(dir.file("empty")));
    EXPECT_EQ(files("empty"), 0u);
    // A symbolic link to an empty folder: the series goes where it points; the link stays.
    std::filesystem::create_directory(dir.file("real"));
    std::filesystem::create_directory_symlink(dir.file("real"), dir.file("link"));
    r = test::runCommand(cli + " export-dicom " + dir.file("u8.nrrd") + " --patient P -o " + dir.file("link"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(std::filesystem::is_symlink(dir.file("link")));
    EXPECT_EQ(files("real"), 5u);
    // -o and --output are one option: both given is refused.
    r = test::runCommand(cli + " export-dicom " + dir.file("u8.nrrd") + " -o " + dir.file("a") + " --output " + dir.file("b"));
    EXPECT_NE(r.output.find("is given twice"), std::string::npos) << r.output;
    // Rows and columns not perpendicular: no DICOM orientation states it.
    r = test::runCommand(cli + " export-dicom " + dir.file("shear.nrrd") + " --patient P -o " + dir.file("shear"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("rows and columns are not perpendicular"), std::string::npos) << r.output;
    // One float CT value of 3e8 would move every HU by thousands.
    r = test::runCommand(cli + " export-dicom " + dir.file("outlier.nrrd") + " --modality CT --patient P -o " + dir.file("f"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("is a value wrong?"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("f")));
    // An octree is not a source.
    r = test::runCommand(cli + " export-dicom " + dir.file("x.hvo") + " -o " + dir.file("x"));
    EXPECT_NE(r.output.find("not its octree"), std::string::npos) << r.output;
}
