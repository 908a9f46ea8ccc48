// The command line's smaller commands, each checked by what it writes, read by an independent
// reader: `gl-info` names a GL 4.5 core context; `dicom-info` agrees with pydicom; `lightfield`
// writes each output format at the size the display needs (PNGs read by VTK's reader from
// python3-vtk9, the multi-part EXR by OpenEXR's exrheader), neighbouring views differ (the
// parallax), and the projector simulator writes the observer's view; `measure` and `slice`
// against numpy over VTK's reading of the same NRRD.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string cli = HVX_CLI;

/// "W H C MEAN" of a PNG as VTK reads it.
std::string pngStats(const std::string& path) {
    const auto r = test::runCommand(
        "/usr/bin/python3 -c \"import vtk, sys; from vtk.util.numpy_support import vtk_to_numpy; "
        "r = vtk.vtkPNGReader(); r.SetFileName(sys.argv[1]); r.Update(); i = r.GetOutput(); d = i.GetDimensions(); "
        "a = vtk_to_numpy(i.GetPointData().GetScalars()); "
        "print(d[0], d[1], i.GetNumberOfScalarComponents(), round(float(a[:, :3].mean()), 3))\" " +
        path + " 2>&1");
    return r.exitCode == 0 ? r.output.substr(0, r.output.find('\n')) : "unreadable: " + r.output;
}

std::string size(const std::string& stats) { return stats.substr(0, stats.find(' ', stats.find(' ') + 1)); }
double mean(const std::string& stats) { return std::stod(stats.substr(stats.rfind(' ') + 1)); }
}  // namespace

TEST(CliCommands, GlInfoNamesAnOpenGl45CoreContext) {
    const auto r = test::runCommand(cli + " gl-info");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("OpenGL 4.5 core"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("renderer "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("(Core Profile)"), std::string::npos) << r.output;
}

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

TEST(CliCommands, LightFieldWritesEveryFormatAtTheDisplaysSize) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand(cli + " phantom --size 32x32x32 -o " + dir.file("p.hvo")).exitCode, 0);
    const std::string lf = cli + " lightfield " + dir.file("p.hvo") + " --zoom 3";
    // Quilt: 11 x 6 views of 64x96 for the Looking Glass Go, named as its software expects.
    auto r = test::runCommand(lf + " --display looking-glass-go --format quilt --size 64x96 -o " + dir.file("q"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string quilt = dir.file("q_qs11x6a0.5625.png");
    const auto qs = pngStats(quilt);
    EXPECT_EQ(size(qs), "704 576") << qs;
    EXPECT_GT(mean(qs), 1.0) << "the quilt shows the volume: " << qs;
    // Projectors: one PNG per view; neighbouring views differ (they look from other angles).
    r = test::runCommand(lf + " --display looking-glass-go --format projectors --size 64x96 -o " + dir.file("views"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::size_t views = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.file("views"))) ++views;
    EXPECT_EQ(views, 66u);
    EXPECT_EQ(size(pngStats(dir.file("views/view_000.png"))), "64 96");
    EXPECT_NE(test::runCommand("cmp -s " + dir.file("views/view_000.png") + " " + dir.file("views/view_065.png")).exitCode,
              0)
        << "the first and last views are the same image: no parallax";
    // EXR: one multi-part file, a part per view, as OpenEXR's own tool lists it.
    r = test::runCommand(lf + " --display looking-glass-go --format exr --size 64x96 -o " + dir.file("views.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto header = test::runCommand("exrheader " + dir.file("views.exr") + " 2>&1");
    ASSERT_EQ(header.exitCode, 0) << "exrheader (Debian's openexr, installer/install-deps.sh): " << header.output;
    std::size_t parts = 0;
    for (std::size_t at = 0; (at = header.output.find("dataWindow", at)) != std::string::npos; ++at) ++parts;
    EXPECT_EQ(parts, 66u) << header.output.substr(0, 600);
    EXPECT_NE(header.output.find("(0 0) - (63 95)"), std::string::npos) << header.output.substr(0, 600);
    // Stereo: a side-by-side pair, twice the width of one view.
    r = test::runCommand(lf + " --display stereo-side-by-side --format stereo --size 64x96 -o " + dir.file("pair.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(size(pngStats(dir.file("pair.png"))), "128 96");
    // DVI frames of the 96-projector HoloVizio: its 320x240 projector images, packed 16 per frame.
    r = test::runCommand(lf + " --display holovizio-96 --format dvi --size 64x48 -o " + dir.file("dvi"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("needs 320x240"), std::string::npos) << r.output;
    r = test::runCommand(lf + " --display holovizio-96 --format dvi --size 320x240 -o " + dir.file("dvi"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (int f = 0; f < 6; ++f)
        EXPECT_EQ(size(pngStats(dir.file("dvi/dvi_frame_0" + std::to_string(f) + ".png"))), "1280 1024") << f;
    // The simulator: what an observer in front of the projector array sees.
    r = test::runCommand(lf + " --display holovizio-96 --format projectors --size 80x60 -o " + dir.file("holo") +
                         " --observer 0,0,1000 --simulate " + dir.file("seen.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto seen = pngStats(dir.file("seen.png"));
    EXPECT_EQ(size(seen), "80 60") << seen;
    EXPECT_GT(mean(seen), 1.0) << seen;
    r = test::runCommand(lf + " --display looking-glass-go --format quilt --size 64x96 -o " + dir.file("q2") +
                         " --observer 0,0,1000 --simulate " + dir.file("no.png"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("needs a projector-array display"), std::string::npos) << r.output;
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
}

// slice: an axial plane through voxel centres, windowed, read back by VTK's PNG reader, equals
// numpy's windowing of the same voxels of the NRRD; a thick-slab MIP equals numpy's maximum over
// the slab; the printed edge letters are the radiological ones.
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
