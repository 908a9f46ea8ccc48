// The command line's smaller commands, each checked by what it writes, read by an independent
// reader: `dicom-info` agrees with pydicom; `measure` and `slice` against numpy over VTK's
// reading of the same NRRD. (The commands that draw with OpenGL are in
// tests/render/CliGlCommandsTest.cpp, with the render label.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string cli = HVX_CLI;

}  // namespace

TEST(CliCommands, DicomInfoAgreesWithPydicom) {
    test::TempDir dir;
    auto r = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) + "/tests/support/dicom_cases.py " +
                              dir.file("cases"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::string file;
    for (const auto& e : std::filesystem::directory_iterator(dir.file("cases/echo"))) file = e.path().string();
    const auto theirs = test::runCommand("/usr/bin/python3 -c \"import pydicom, sys; d = pydicom.dcmread(sys.argv[1]); "
                                         "print(d.Modality, d.PatientName, d.PatientID, d.Columns, d.Rows)\" " + file);
    ASSERT_EQ(theirs.exitCode, 0) << theirs.output;
    char modality[16], name[64], id[64];
    int columns = 0, rows = 0;
    ASSERT_EQ(std::sscanf(theirs.output.c_str(), "%15s %63s %63s %d %d", modality, name, id, &columns, &rows), 5);
    r = test::runCommand(cli + " dicom-info " + file);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find(std::string(modality) + " "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("'" + std::string(name) + "' (" + id + ")"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(std::to_string(columns) + "x" + std::to_string(rows) + "x1"), std::string::npos) << r.output;
    r = test::runCommand(cli + " dicom-info " + dir.file("not-there.dcm"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("not-there.dcm"), std::string::npos) << r.output;
}

namespace {
/// Runs a Python script (written to `dir`) with /usr/bin/python3; returns its output.
test::ProcessResult python(const test::TempDir& dir, const std::string& name, const std::string& script,
                           const std::string& args) {
    std::ofstream(dir.file(name)) << script;
    return test::runCommand("/usr/bin/python3 " + dir.file(name) + " " + args + " 2>&1");
}

double field(const std::string& output, const std::string& name) {
    const auto at = output.find("  " + name + " ");
    if (at == std::string::npos) return std::nan("");
    return std::strtod(output.c_str() + at + name.size() + 2, nullptr);
}
}  // namespace

// measure: a sphere's voxels, mean, SD, min and max against numpy over the same NRRD read by
// VTK's NRRD reader (a voxel counts when its centre lies in the sphere).
TEST(CliCommands, MeasureAgreesWithNumpyOverVtksReadingOfTheSameFile) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand(cli + " phantom --size 40x36x30 -o " + dir.file("p.nrrd")).exitCode, 0);
    ASSERT_EQ(test::runCommand(cli + " build " + dir.file("p.nrrd") + " --brick 8 -o " + dir.file("p.hvo")).exitCode, 0);
    const std::string oracle =
        "import sys, numpy as np\n"
        "from vtkmodules.vtkIOImage import vtkNrrdReader\n"
        "from vtkmodules.util.numpy_support import vtk_to_numpy\n"
        "r = vtkNrrdReader(); r.SetFileName(sys.argv[1]); r.Update()\n"
        "img = r.GetOutput(); nx, ny, nz = img.GetDimensions(); sp = img.GetSpacing(); org = img.GetOrigin()\n"
        "a = vtk_to_numpy(img.GetPointData().GetScalars()).astype(np.float64).reshape(nz, ny, nx)\n"
        "cx, cy, cz, rad = map(float, sys.argv[2].split(','))\n"
        "k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing='ij')\n"
        "m = (org[0] + i * sp[0] - cx) ** 2 + (org[1] + j * sp[1] - cy) ** 2 + (org[2] + k * sp[2] - cz) ** 2 <= rad * rad\n"
        "v = a[m]\n"
        "print(int(m.sum()), repr(float(v.mean())), repr(float(v.std())), repr(float(v.min())), repr(float(v.max())))\n";
    for (const std::string sphere : {"10,-20,5,60", "-100,40,-60,95.5"}) {
        const auto theirs = python(dir, "oracle.py", oracle, dir.file("p.nrrd") + " " + sphere);
        ASSERT_EQ(theirs.exitCode, 0) << theirs.output;
        unsigned long voxels = 0;
        double mean = 0, sd = 0, min = 0, max = 0;
        ASSERT_EQ(std::sscanf(theirs.output.c_str(), "%lu %lf %lf %lf %lf", &voxels, &mean, &sd, &min, &max), 5)
            << theirs.output;
        const auto r = test::runCommand(cli + " measure " + dir.file("p.hvo") + " --roi sphere:" + sphere);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_EQ(field(r.output, "voxels"), double(voxels)) << r.output;
        EXPECT_NEAR(field(r.output, "mean"), mean, 1e-4 * std::max(1.0, std::abs(mean))) << r.output;
        EXPECT_NEAR(field(r.output, "sd"), sd, 1e-4 * std::max(1.0, sd)) << r.output;
        EXPECT_EQ(field(r.output, "min"), min) << r.output;
        EXPECT_EQ(field(r.output, "max"), max) << r.output;
        EXPECT_NE(r.output.find("HU"), std::string::npos) << r.output;
    }
    auto r = test::runCommand(cli + " measure " + dir.file("p.hvo") + " --roi sphere:5000,0,0,10");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("outside the volume"), std::string::npos) << r.output;
    r = test::runCommand(cli + " measure " + dir.file("p.hvo") + " --roi ellipse:1,2");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("is not a region"), std::string::npos) << r.output;
    // Two regions given: which was meant is not guessed (the last had been measured).
    r = test::runCommand(cli + " measure " + dir.file("p.hvo") + " --roi sphere:0,0,0,2 --roi sphere:0,0,0,8");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("option --roi is given twice"), std::string::npos) << r.output;
    // A circle drawn on a slice (a disc) gives its area as well as its volume.
    r = test::runCommand(cli + " measure " + dir.file("p.hvo") + " --roi disc:10,-20,5,0,0,1,30,20");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("  area    "), std::string::npos) << r.output;
}

// slice: an axial plane through voxel centres, windowed, read back by VTK's PNG reader, equals
// numpy's windowing of the same voxels of the NRRD; a thick-slab MIP equals numpy's maximum over
// the slab; the printed edge letters are the radiological ones.
// slice without --at, through a volume of eight 3 mm slices whose centre lies between layers 3
// and 4: the image is layer 4 as stored (numpy's own values through VTK's PNG reader), where it
// had been the mean of the two layers at every pixel.
TEST(CliCommands, SliceWithoutAtShowsAnAcquiredLayer) {
    test::TempDir dir;
    const std::string writer =
        "import sys, numpy as np\n"
        "a = (10 * np.arange(8)[:, None, None] + np.arange(16)[None, None, :] + 0 * np.arange(16)[None, :, None])"
        ".astype('<i2')\n"  // z, y, x: 10 k + i
        "open(sys.argv[1], 'wb').write(b'NRRD0004\\ntype: int16\\ndimension: 3\\nspace: left-posterior-superior\\n'\n"
        "  b'sizes: 16 16 8\\nspace directions: (0.5,0,0) (0,0.8,0) (0,0,3)\\nspace origin: (0,0,0)\\n'\n"
        "  b'endian: little\\nencoding: raw\\n\\n' + a.tobytes())\n";
    auto w = python(dir, "write.py", writer, dir.file("v.nrrd"));
    ASSERT_EQ(w.exitCode, 0) << w.output;
    ASSERT_EQ(test::runCommand(cli + " build " + dir.file("v.nrrd") + " -o " + dir.file("v.hvo")).exitCode, 0);
    auto r = test::runCommand(cli + " slice " + dir.file("v.hvo") + " --plane axial --size 16x1 --pixel 0.5 "
                              "--window 255,127.5 -o " + dir.file("ax.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("through (3.75, 6, 12)"), std::string::npos) << r.output;
    const std::string check =
        "import sys, numpy as np\n"
        "from vtkmodules.vtkIOImage import vtkPNGReader\n"
        "from vtkmodules.util.numpy_support import vtk_to_numpy\n"
        "p = vtkPNGReader(); p.SetFileName(sys.argv[1]); p.Update()\n"
        "got = vtk_to_numpy(p.GetOutput().GetPointData().GetScalars()).reshape(-1).astype(int)\n"
        "want = 40 + np.arange(16)\n"  // layer 4; i runs to the patient's left, the image's right
        "print(int(np.abs(got - want).max()))\n";
    const auto c = python(dir, "check.py", check, dir.file("ax.png"));
    ASSERT_EQ(c.exitCode, 0) << c.output;
    EXPECT_EQ(c.output, "0\n") << "largest grey difference from layer 4";
}

TEST(CliCommands, SliceAndSlabAgreeWithNumpyOnTheSameVoxels) {
    test::TempDir dir;
    const std::string writer =
        "import sys, numpy as np\n"
        "rng = np.random.default_rng(5)\n"
        "a = rng.integers(-1000, 2000, size=(24, 30, 34)).astype('<i2')\n"  // z, y, x
        "open(sys.argv[1], 'wb').write(b'NRRD0004\\ntype: int16\\ndimension: 3\\nspace: left-posterior-superior\\n'\n"
        "  b'sizes: 34 30 24\\nspace directions: (1,0,0) (0,1,0) (0,0,1)\\nspace origin: (10,20,30)\\n'\n"
        "  b'endian: little\\nencoding: raw\\n\\n' + a.tobytes())\n";
    auto w = python(dir, "write.py", writer, dir.file("v.nrrd"));
    ASSERT_EQ(w.exitCode, 0) << w.output;
    ASSERT_EQ(test::runCommand(cli + " build " + dir.file("v.nrrd") + " --brick 8 -o " + dir.file("v.hvo")).exitCode, 0);
    // Voxel (17, 15, 12) at the centre of a 21 x 19 image of 1 mm pixels: pixel (i, j) is voxel
    // (7 + i, 6 + j, 12).
    const std::string at = " --at 27,35,42 --size 21x19 --pixel 1 --window 1200,300";
    auto r = test::runCommand(cli + " slice " + dir.file("v.hvo") + " --plane axial" + at + " -o " + dir.file("ax.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("edges: left R, right L, top A, bottom P"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("level 0"), std::string::npos) << r.output;
    r = test::runCommand(cli + " slice " + dir.file("v.hvo") + " --plane axial --slab 4 --slab-mode mip" + at + " -o " +
                         dir.file("mip.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("slab 4 mm (5 samples)"), std::string::npos) << r.output;
    const std::string check =
        "import sys, numpy as np\n"
        "from vtkmodules.vtkIOImage import vtkNrrdReader, vtkPNGReader\n"
        "from vtkmodules.util.numpy_support import vtk_to_numpy\n"
        "r = vtkNrrdReader(); r.SetFileName(sys.argv[1]); r.Update()\n"
        "v = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).astype(float).reshape(24, 30, 34)\n"
        "def png(path):\n"
        "  p = vtkPNGReader(); p.SetFileName(path); p.Update(); d = p.GetOutput().GetDimensions()\n"
        "  return np.flipud(vtk_to_numpy(p.GetOutput().GetPointData().GetScalars()).reshape(d[1], d[0]))\n"
        "def window(x):\n"
        "  return np.floor(np.clip((x - (300 - 600)) / 1200, 0, 1) * 255 + 0.5)\n"
        "ax = window(v[12, 6:25, 7:28]); mip = window(v[10:15, 6:25, 7:28].max(axis=0))\n"
        "print(int(np.abs(png(sys.argv[2]) - ax).max()), int(np.abs(png(sys.argv[3]) - mip).max()))\n";
    const auto c = python(dir, "check.py", check, dir.file("v.nrrd") + " " + dir.file("ax.png") + " " + dir.file("mip.png"));
    ASSERT_EQ(c.exitCode, 0) << c.output;
    int axial = -1, mip = -1;
    ASSERT_EQ(std::sscanf(c.output.c_str(), "%d %d", &axial, &mip), 2) << c.output;
    EXPECT_LE(axial, 1) << "largest grey difference of the axial slice";
    EXPECT_LE(mip, 1) << "largest grey difference of the slab MIP";
    // --scroll 4 steps a slice (1 mm here) three times: its last image is the slice 3 mm up,
    // which the numpy check above vouches for at its own plane.
    r = test::runCommand(cli + " slice " + dir.file("v.hvo") + " --plane axial --scroll 4" + at + " -o " + dir.file("s.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("scrolled 4 slices 1 mm apart"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("through (27, 35, 45)"), std::string::npos) << r.output;
    const std::string up = " --at 27,35,45 --size 21x19 --pixel 1 --window 1200,300";
    ASSERT_EQ(test::runCommand(cli + " slice " + dir.file("v.hvo") + " --plane axial" + up + " -o " + dir.file("up.png")).exitCode, 0);
    const auto bytes = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    EXPECT_EQ(bytes(dir.file("s.png")), bytes(dir.file("up.png")));
    EXPECT_NE(test::runCommand(cli + " slice " + dir.file("v.hvo") + " --scroll 0" + at + " -o " + dir.file("z.png")).exitCode, 0);
    r = test::runCommand(cli + " slice " + dir.file("v.hvo") + " --plane coronal" + at + " -o " + dir.file("co.png"));
    EXPECT_NE(r.output.find("edges: left R, right L, top S, bottom I"), std::string::npos) << r.output;
    r = test::runCommand(cli + " slice " + dir.file("v.hvo") + " --plane 0,0,0" + at + " -o " + dir.file("no.png"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("normal of non-zero length"), std::string::npos) << r.output;
    r = test::runCommand(cli + " slice " + dir.file("v.hvo") + " --plane axial --at 900,900,900 -o " + dir.file("out.png"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("does not cross the volume"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("out.png")));
}

// version: every library with its version as linked; DCMTK's is the one DCMTK's own dcmdump
// reports, SQLite's the one Python's sqlite3 module (the same shared library) reports.
TEST(CliCommands, VersionListsTheLibrariesAsLinked) {
    const auto r = test::runCommand(cli + " version");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* lib : {"DCMTK", "libcurl", "OpenSSL", "SQLite", "OpenJPEG", "VTK", "zstd", "LZ4", "xxHash", "OpenEXR",
                            "libpng", "GLM"})
        EXPECT_NE(r.output.find(std::string("  ") + lib + " "), std::string::npos) << lib << "\n" << r.output;
    const auto dcmdump = test::runCommand("dcmdump --version");
    const auto v = dcmdump.output.find(" v");
    ASSERT_NE(v, std::string::npos) << dcmdump.output;
    const std::string dcmtk = dcmdump.output.substr(v + 2, dcmdump.output.find(' ', v + 2) - v - 2);
    EXPECT_NE(r.output.find("DCMTK     " + dcmtk + "\n"), std::string::npos) << dcmtk << "\n" << r.output;
    const auto py = test::runCommand("/usr/bin/python3 -c \"import sqlite3; print(sqlite3.sqlite_version)\"");
    EXPECT_NE(r.output.find("SQLite    " + py.output), std::string::npos) << py.output << r.output;
}

// label-stats against numpy over nibabel's reading of the same NIfTI files (a label map on its
// own rotated, coarser grid), and slice --labels / --overlay drawing and refusing.
TEST(CliCommands, LabelStatsAgreeWithNumpyAndSlicesDrawLabels) {
    test::TempDir dir;
    const auto oracle = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) +
                                         "/tests/support/label_stats_oracle.py " + dir.path().string());
    ASSERT_EQ(oracle.exitCode, 0) << oracle.output;
    ASSERT_EQ(test::runCommand(cli + " build " + dir.file("image.nii.gz") + " -o " + dir.file("image.hvo")).exitCode, 0);
    auto r = test::runCommand(cli + " build " + dir.file("labels.nii.gz") + " --labels -o " + dir.file("labels.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " label-stats " + dir.file("image.hvo") + " " + dir.file("labels.hvo") + " -o " +
                         dir.file("stats.csv") + " 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("label(s) 9 reach outside the image"), std::string::npos) << r.output;
    std::ifstream csv(dir.file("stats.csv"));
    std::string header, line;
    std::getline(csv, header);
    EXPECT_EQ(header, "label,name,voxels,volume_ml,voxels_in_image,mean,sd,min,max,units,exact");
    std::istringstream want(oracle.output);
    int rows = 0;
    while (std::getline(csv, line)) {
        std::string wantLine;
        ASSERT_TRUE(std::getline(want, wantLine)) << "an extra row: " << line;
        int label = 0, wl = 0;
        char name[64];
        unsigned long long voxels = 0, inside = 0, wv = 0, wi = 0;
        double ml = 0, mean = 0, sd = 0, wml = 0, wmean = 0, wsd = 0;
        ASSERT_EQ(std::sscanf(line.c_str(), "%d,\"%63[^\"]\",%llu,%lf,%llu,%lf,%lf", &label, name, &voxels, &ml, &inside,
                              &mean, &sd), 7) << line;
        ASSERT_EQ(std::sscanf(wantLine.c_str(), "%d,%llu,%lf,%llu,%lf,%lf", &wl, &wv, &wml, &wi, &wmean, &wsd), 6);
        EXPECT_EQ(label, wl);
        EXPECT_EQ(voxels, wv) << label;
        EXPECT_NEAR(ml, wml, 1e-6) << label;
        EXPECT_EQ(inside, wi) << label;
        EXPECT_NEAR(mean, wmean, 1e-3 * std::max(1.0, std::abs(wmean))) << label;
        EXPECT_NEAR(sd, wsd, 1e-3 * std::max(1.0, wsd)) << label;
        ++rows;
    }
    EXPECT_EQ(rows, 2);
    // The label map over the image in a slice: an RGB PNG, the legend printed.
    r = test::runCommand(cli + " slice " + dir.file("image.hvo") + " --plane axial --at 5,2,0 --labels " +
                         dir.file("labels.hvo") + " -o " + dir.file("l.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("labels " + dir.file("labels.hvo") + " (generated colours): 3 label 3"), std::string::npos)
        << r.output;
    const auto png = test::runCommand("/usr/bin/python3 -c \"import sys; b=open(sys.argv[1],'rb').read(); print(b[25])\" " +
                                      dir.file("l.png"));
    EXPECT_EQ(png.output, "2\n");  // PNG colour type 2: RGB
    // Refusals: an intensity volume as labels, an unknown colour map.
    r = test::runCommand(cli + " slice " + dir.file("image.hvo") + " --labels " + dir.file("image.hvo") + " -o " +
                         dir.file("x.png") + " 2>&1");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("is not a label map"), std::string::npos) << r.output;
    r = test::runCommand(cli + " slice " + dir.file("image.hvo") + " --overlay " + dir.file("image.hvo") +
                         ":lut=viridian -o " + dir.file("x.png") + " 2>&1");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("no colour map named \"viridian\""), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.png")));
}

// A DICOM SEG written by pydicom built into a label map: its segments' names and colours kept
// beside the octree, and used by slice --labels and label-stats without being asked for.
TEST(CliCommands, SegmentationBuildsALabelMapWithItsOwnTable) {
    test::TempDir dir;
    auto r = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) + "/tests/support/seg_cases.py " +
                              dir.path().string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " build " + dir.file("binary.dcm") + " -o " + dir.file("seg.hvo") + " --quiet 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream table(dir.file("seg.hvo.ctbl"));
    const std::string text((std::istreambuf_iterator<char>(table)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\n1 liver "), std::string::npos) << text;
    EXPECT_NE(text.find("\n2 spleen "), std::string::npos) << text;
    r = test::runCommand(cli + " info " + dir.file("seg.hvo"));
    EXPECT_NE(r.output.find("label"), std::string::npos) << r.output;
    r = test::runCommand(cli + " slice " + dir.file("seg.hvo") + " --plane axial --labels " + dir.file("seg.hvo") +
                         " -o " + dir.file("s.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("(3D Slicer colour table): 1 liver"), std::string::npos) << r.output;
    r = test::runCommand(cli + " label-stats " + dir.file("seg.hvo") + " " + dir.file("seg.hvo") + " 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("1,\"liver\","), std::string::npos) << r.output;
    // Without frame positions: refused, nothing written.
    r = test::runCommand(cli + " build " + dir.file("noposition.dcm") + " -o " + dir.file("bad.hvo") + " 2>&1");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("has no position"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.hvo")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.hvo.ctbl")));
}

// An RT Structure Set written by pydicom, imported with its CT: drawn onto the CT's grid (build
// --grid, or build-series from the database), each ROI's voxel count equal to numpy's
// point-in-polygon count over the same voxel centres (rt_labels.txt), its ROIs' names kept;
// without a grid it is refused with a sentence, and a contour past the image is said.
TEST(CliCommands, StructureSetIsDrawnOntoItsImagesGrid) {
    test::TempDir dir;
    auto r = test::runCommand("/usr/bin/python3 " + std::string(HVX_SOURCE_DIR) + "/tests/support/seg_cases.py " +
                              dir.path().string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string db = " --db " + dir.file("s.db");
    r = test::runCommand(cli + " import " + dir.path().string() + db + " 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("RT structure sets"), std::string::npos) << r.output;
    r = test::runCommand(cli + " studies" + db);
    auto uidOf = [&](const std::string& modality) {
        const auto at = r.output.find(" " + modality + " ");
        if (at == std::string::npos) return std::string();
        const auto end = r.output.find('\n', at);
        const auto line = r.output.substr(at, end - at);
        return line.substr(line.rfind(' ') + 1);
    };
    const std::string ctUid = uidOf("CT  "), rtUid = uidOf("RTSTRUCT");
    ASSERT_FALSE(ctUid.empty() || rtUid.empty()) << r.output;
    ASSERT_EQ(test::runCommand(cli + " build-series " + ctUid + db + " -o " + dir.file("ct.hvo")).exitCode, 0);
    r = test::runCommand(cli + " build " + dir.file("rtstruct.dcm") + " -o " + dir.file("rt.hvo") + " 2>&1");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("--grid IMAGE.hvo"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("rt.hvo")));
    r = test::runCommand(cli + " build " + dir.file("rtstruct.dcm") + " --grid " + dir.file("ct.hvo") + " -o " +
                         dir.file("rt.hvo") + " --quiet 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("of beyond lie past the image's slices"), std::string::npos) << r.output;
    std::map<int, int> expected;  // numpy's label per voxel centre
    std::ifstream oracle(dir.file("rt_labels.txt"));
    for (double x, y, z; oracle >> x >> y >> z;) {
        int label = 0;
        oracle >> label;
        ++expected[label];
    }
    ASSERT_GT(expected[1], 100);
    ASSERT_GT(expected[2], 100);
    r = test::runCommand(cli + " label-stats " + dir.file("ct.hvo") + " " + dir.file("rt.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("1,\"GTV\"," + std::to_string(expected[1]) + ","), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("2,\"R\u00fcckenmark\"," + std::to_string(expected[2]) + ","), std::string::npos) << r.output;
    r = test::runCommand(cli + " build-series " + rtUid + db + " --grid " + dir.file("ct.hvo") + " -o " + dir.file("rt2.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto a = test::runCommand("cmp " + dir.file("rt.hvo") + " " + dir.file("rt2.hvo"));
    EXPECT_EQ(a.exitCode, 0) << "the same structure set drawn twice differs: " << a.output;
}
