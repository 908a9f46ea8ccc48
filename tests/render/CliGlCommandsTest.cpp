// The command line's OpenGL commands, each checked by what it writes, read by an independent
// reader: `gl-info` names a GL 4.5 core context; `lightfield` writes each output format at the
// size the display needs (PNGs read by VTK's reader from python3-vtk9, the multi-part EXR by
// OpenEXR's exrheader), neighbouring views differ (the parallax), and the projector simulator
// writes the observer's view. Render label: run by the ci suite and under ThreadSanitizer, not
// under ASan (Mesa's llvmpipe keeps allocations LeakSanitizer reports, as for every render test).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string cli = HVX_CLI;

/// "W H C MEAN" of a PNG as VTK reads it.
std::string pngStats(const std::string& path) {
    const auto r = test::runCommand(
        "/usr/bin/python3 -c \"import sys; from vtkmodules.vtkIOImage import vtkPNGReader; "
        "from vtkmodules.util.numpy_support import vtk_to_numpy; "
        "r = vtkPNGReader(); r.SetFileName(sys.argv[1]); r.Update(); i = r.GetOutput(); d = i.GetDimensions(); "
        "a = vtk_to_numpy(i.GetPointData().GetScalars()); "
        "print(d[0], d[1], i.GetNumberOfScalarComponents(), round(float(a[:, :3].mean()), 3))\" " +
        path + " 2>&1");
    return r.exitCode == 0 ? r.output.substr(0, r.output.find('\n')) : "unreadable: " + r.output;
}

/// Liver-red (145, 30, 35) and spleen-blue (0, 119, 192) pixels of a PNG as VTK reads it (lit:
/// red-dominant and blue-dominant).
std::pair<int, int> segmentPixels(const std::string& png) {
    const auto counts = test::runCommand(
        "/usr/bin/python3 -c \"import sys; from vtkmodules.vtkIOImage import vtkPNGReader; "
        "from vtkmodules.util.numpy_support import vtk_to_numpy; "
        "r = vtkPNGReader(); r.SetFileName(sys.argv[1]); r.Update(); "
        "a = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).astype(int); "
        "print(int(((a[:, 0] > a[:, 2] + 40) & (a[:, 0] > a[:, 1] + 40)).sum()), int((a[:, 2] > a[:, 0] + 40).sum()))\" " +
        png);
    int liver = -1, spleen = -1;
    if (counts.exitCode != 0 || std::sscanf(counts.output.c_str(), "%d %d", &liver, &spleen) != 2)
        ADD_FAILURE() << png << ": " << counts.output;
    return {liver, spleen};
}

/// The mean absolute difference of two PNGs' RGB values (0–255) as VTK reads them.
double pngDifference(const std::string& a, const std::string& b) {
    const auto r = test::runCommand(
        "/usr/bin/python3 -c \"import sys; from vtkmodules.vtkIOImage import vtkPNGReader; "
        "from vtkmodules.util.numpy_support import vtk_to_numpy\n"
        "def rgb(f):\n r = vtkPNGReader(); r.SetFileName(f); r.Update()\n"
        " return vtk_to_numpy(r.GetOutput().GetPointData().GetScalars())[:, :3].astype(float)\n"
        "print(abs(rgb(sys.argv[1]) - rgb(sys.argv[2])).mean())\" " +
        a + " " + b + " 2>&1");
    if (r.exitCode != 0) ADD_FAILURE() << r.output;
    return r.exitCode == 0 ? std::stod(r.output) : -1.0;
}

std::string size(const std::string& stats) { return stats.substr(0, stats.find(' ', stats.find(' ') + 1)); }
double mean(const std::string& stats) { return std::stod(stats.substr(stats.rfind(' ') + 1)); }
}  // namespace

TEST(CliGlCommands, GlInfoNamesAnOpenGl45CoreContext) {
    const auto r = test::runCommand(cli + " gl-info");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("OpenGL 4.5 core"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("renderer "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("(Core Profile)"), std::string::npos) << r.output;
}

TEST(CliGlCommands, LightFieldWritesEveryFormatAtTheDisplaysSize) {
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
    // What the frames hold, read back by VTK: the second frame's 16 tiles are projectors 16-31's
    // own images (as `--format projectors` writes them), pixel for pixel, under header blocks
    // coding their ids (R = id, G = 0, B = 255).
    r = test::runCommand(lf + " --display holovizio-96 --format projectors --size 320x240 -o " + dir.file("proj"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto dvi = test::runCommand(
        "/usr/bin/python3 -c \"import sys; from vtkmodules.vtkIOImage import vtkPNGReader; "
        "from vtkmodules.util.numpy_support import vtk_to_numpy\n"
        "def read(p):\n"
        "    r = vtkPNGReader(); r.SetFileName(p); r.Update(); w, h, _ = r.GetOutput().GetDimensions()\n"
        "    return vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(h, w, -1)[::-1, :, :3].astype(int)\n"
        "f = read(sys.argv[1] + '/dvi/dvi_frame_01.png'); worst = 0; ids = 0\n"
        "for k in range(16):\n"
        "    v = read(sys.argv[1] + '/proj/view_%03d.png' % (16 + k)); y, x = 64 + (k // 4) * 240, (k % 4) * 320\n"
        "    worst = max(worst, abs(f[y:y + 240, x:x + 320] - v).max())\n"
        "    ids += int((f[32, k * 80 + 40] == [16 + k, 0, 255]).all())\n"
        "print(worst, ids)\" " + dir.path().string());
    int worstTile = -1, idBlocks = 0;
    ASSERT_EQ(std::sscanf(dvi.output.c_str(), "%d %d", &worstTile, &idBlocks), 2) << dvi.output;
    EXPECT_EQ(worstTile, 0) << "a DVI tile differs from its projector's image";
    EXPECT_EQ(idBlocks, 16) << "header blocks not coding projectors 16-31";
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


// `render` of a label map (a DICOM SEG written by pydicom): the segments in their own colours
// (the table kept beside the octree), counted by VTK's PNG reader; a --tf preset on a label map
// and --lut on an image are refused with a sentence.
TEST(CliGlCommands, RenderDrawsALabelMapInItsSegmentsColours) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand("/usr/bin/python3 " HVX_SOURCE_DIR "/tests/support/seg_cases.py " + dir.path().string()).exitCode, 0);
    auto r = test::runCommand(cli + " build " + dir.file("binary.dcm") + " -o " + dir.file("seg.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " render " + dir.file("seg.hvo") + " --view 30,20,1 --size 128x128 -o " + dir.file("seg.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("tf labels (3D Slicer colour table)"), std::string::npos) << r.output;
    // Liver (145, 30, 35) and spleen (0, 119, 192), lit: red-dominant and blue-dominant pixels.
    const auto [liver, spleen] = segmentPixels(dir.file("seg.png"));
    EXPECT_GT(liver, 300);
    EXPECT_GT(spleen, 50);
    r = test::runCommand(cli + " render " + dir.file("seg.hvo") + " --tf ct-bone -o " + dir.file("x.png"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("label table"), std::string::npos) << r.output;
    ASSERT_EQ(test::runCommand(cli + " phantom --size 16x16x16 -o " + dir.file("p.hvo")).exitCode, 0);
    r = test::runCommand(cli + " render " + dir.file("p.hvo") + " --lut " + dir.file("seg.hvo.ctbl") + " -o " + dir.file("y.png"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("is not a label map"), std::string::npos) << r.output;
}

// pydicom's SEG built as a split-voxel octree (from its plain octree) and drawn
// by the GPU's split-voxel variant and by the CPU reference: the same segments' colours (VTK
// reads both PNGs) and the same mean colour; a light-field quilt of a split-voxel CT phantom
// drawn alike by both.
TEST(CliGlCommands, RenderDrawsASplitVoxelLabelMapOnTheGpuAsTheCpuDoes) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand("/usr/bin/python3 " HVX_SOURCE_DIR "/tests/support/seg_cases.py " + dir.path().string()).exitCode, 0);
    // Built from the plain octree (its level 0 read back), the label names and colours follow.
    auto r = test::runCommand(cli + " build " + dir.file("binary.dcm") + " -o " + dir.file("plain.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " build " + dir.file("plain.hvo") + " --split-voxels -o " + dir.file("seg.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::vector<double> means;
    for (const std::string how : {"", " --cpu"}) {
        const auto png = dir.file(how.empty() ? "gpu.png" : "cpu.png");
        r = test::runCommand(cli + " render " + dir.file("seg.hvo") + how + " --view 30,20,1 --size 128x128 -o " + png);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("tf labels (3D Slicer colour table)"), std::string::npos) << r.output;
        const auto [liver, spleen] = segmentPixels(png);
        EXPECT_GT(liver, 300) << how;
        EXPECT_GT(spleen, 50) << how;
        means.push_back(mean(pngStats(png)));
    }
    EXPECT_NEAR(means[0], means[1], 0.5) << "GPU and CPU means differ";
    // A light-field quilt from a split-voxel CT phantom: the 48 views, GPU as CPU; MIP refused.
    r = test::runCommand(cli + " build phantom:96x96x96 --split-voxels --quiet -o " + dir.file("ps.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::vector<double> quilts;
    for (const std::string how : {"", " --cpu"}) {
        const auto out = dir.file(how.empty() ? "lg" : "lc");
        r = test::runCommand(cli + " lightfield " + dir.file("ps.hvo") + how + " --display looking-glass-portrait --size 60x80 -o " + out);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("48 views of 60x80"), std::string::npos) << r.output;
        const auto stats = pngStats(out + "_qs8x6a0.75.png");
        EXPECT_EQ(size(stats), "480 480") << stats;
        quilts.push_back(mean(stats));
    }
    EXPECT_GT(quilts[0], 1.0);
    EXPECT_NEAR(quilts[0], quilts[1], 0.3) << "GPU and CPU quilts differ";
    r = test::runCommand(cli + " lightfield " + dir.file("ps.hvo") + " --display looking-glass-portrait --mode mip -o " + dir.file("m") + " 2>&1");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("split-voxel octree is drawn in DVR"), std::string::npos) << r.output;
}

// render/lightfield --refraction (thesis §3.2.2): the lungs of the CT phantom under ct-lung
// refract; the image changes, GPU and CPU alike; an index given per HU value (the body as
// water) is converted to stored values; a light-field quilt bends its rays too.
TEST(CliGlCommands, RenderAndLightFieldBendTheRaysWithRefraction) {
    test::TempDir dir;
    auto r = test::runCommand(cli + " build phantom:96x96x80 --quiet -o " + dir.file("p.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::map<std::string, std::string> png;
    for (const std::string how : {"", " --cpu"})
        for (const std::string refraction : {"", " --refraction 1.3", " --refraction=-600:1,-400:1.33"}) {
            png[how + refraction] = dir.file("r" + std::to_string(png.size()) + ".png");
            r = test::runCommand(cli + " render " + dir.file("p.hvo") + how + refraction +
                                 " --tf ct-lung --view 20,15,1 --size 96x96 -o " + png[how + refraction]);
            ASSERT_EQ(r.exitCode, 0) << r.output;
        }
    for (const std::string refraction : {" --refraction 1.3", " --refraction=-600:1,-400:1.33"}) {
        const double change = pngDifference(png[refraction], png[""]);
        const double apart = pngDifference(png[refraction], png[" --cpu" + refraction]);
        std::printf("%s: %.2f from no refraction, GPU and CPU %.2f apart (mean |difference| of 0-255 values)\n",
                    refraction.c_str(), change, apart);
        EXPECT_GT(change, 1.0) << refraction << ": refraction changed nothing";
        EXPECT_LT(apart, change / 5) << refraction << ": GPU and CPU differ";
    }
    std::vector<std::string> quilts;
    for (const std::string refraction : {"", " --refraction 1.3"}) {
        const auto out = dir.file(refraction.empty() ? "straight" : "bent");
        r = test::runCommand(cli + " lightfield " + dir.file("p.hvo") + refraction +
                             " --tf ct-lung --display looking-glass-portrait --size 30x40 -o " + out);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        quilts.push_back(out + "_qs8x6a0.75.png");
    }
    EXPECT_GT(pngDifference(quilts[0], quilts[1]), 2.0) << "the quilt's rays did not bend";
    r = test::runCommand(cli + " lightfield " + dir.file("p.hvo") + " --refraction 1.3 --mode mip --display looking-glass-portrait -o " +
                         dir.file("m") + " 2>&1");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("--mode mip"), std::string::npos) << r.output;
}

// render --labels: pydicom's SEG fused over its CT in one ray march (the CT, 40 HU throughout,
// transparent under ct-bone): the segments' colours show, on the GPU and on the CPU alike;
// --overlay lays an image with a colour map; what cannot be fused is refused with a sentence.
TEST(CliGlCommands, RenderFusesASegmentationOverItsImage) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand("/usr/bin/python3 " HVX_SOURCE_DIR "/tests/support/seg_cases.py " + dir.path().string()).exitCode, 0);
    auto r = test::runCommand(cli + " build " + dir.file("binary.dcm") + " -o " + dir.file("seg.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string db = " --db " + dir.file("s.db");
    ASSERT_EQ(test::runCommand(cli + " import " + dir.file("image") + db).exitCode, 0);
    r = test::runCommand(cli + " studies" + db);
    const auto at = r.output.find("    series ");
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::string line = r.output.substr(at, r.output.find('\n', at) - at);
    r = test::runCommand(cli + " build-series " + line.substr(line.rfind(' ') + 1) + db + " -o " + dir.file("ct.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const std::string device : {"", " --cpu"}) {
        r = test::runCommand(cli + " render " + dir.file("ct.hvo") + " --labels " + dir.file("seg.hvo") + device +
                             " --view 30,20,1 --size 128x128 -o " + dir.file("fused.png"));
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("fused " + dir.file("seg.hvo") + " (labels, 3D Slicer colour table)"), std::string::npos)
            << r.output;
        const auto [liver, spleen] = segmentPixels(dir.file("fused.png"));
        EXPECT_GT(liver, 300) << device;
        EXPECT_GT(spleen, 50) << device;
        // A light-field quilt fuses them in every view.
        r = test::runCommand(cli + " lightfield " + dir.file("ct.hvo") + " --labels " + dir.file("seg.hvo") + device +
                             " --display looking-glass-portrait --size 60x80 -o " + dir.file("lf"));
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("fused " + dir.file("seg.hvo") + " (labels, 3D Slicer colour table)"), std::string::npos)
            << r.output;
        const auto [lfLiver, lfSpleen] = segmentPixels(dir.file("lf_qs8x6a0.75.png"));
        std::printf("light field%s: liver %d, spleen %d pixels over 48 views\n", device.c_str(), lfLiver, lfSpleen);
        EXPECT_GT(lfLiver, 48 * 20) << device;
        EXPECT_GT(lfSpleen, 48 * 4) << device;
    }
    // The CT under a hot colour map over the segmentation's grid's image: shown, said.
    r = test::runCommand(cli + " render " + dir.file("ct.hvo") + " --overlay " + dir.file("ct.hvo") +
                         ":lut=hot,opacity=0.8,window=200/0 --size 64x64 -o " + dir.file("hot.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("(hot map, window W 200 / L 0, opacity 0.8)"), std::string::npos) << r.output;
    for (const auto& [args, sentence] : std::vector<std::pair<std::string, std::string>>{
             {" --labels " + dir.file("seg.hvo") + " --overlay " + dir.file("ct.hvo"), "one volume at a time"},
             {" --labels " + dir.file("seg.hvo") + " --mode mip", "in DVR only"},
             {" --labels " + dir.file("ct.hvo"), "is not a label map"},
             {" --overlay " + dir.file("seg.hvo"), "is a label map: lay it over with --labels"},
             {" --overlay " + dir.file("ct.hvo") + ":opacity=2", "opacity must be 0 to 1"},
             {" --overlay " + dir.file("missing.hvo"), "missing.hvo"}}) {
        r = test::runCommand(cli + " render " + dir.file("ct.hvo") + args + " -o " + dir.file("no.png") + " 2>&1");
        EXPECT_NE(r.exitCode, 0) << args;
        EXPECT_NE(r.output.find(sentence), std::string::npos) << args << ": " << r.output;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("no.png")));
    for (const auto& [args, sentence] : std::vector<std::pair<std::string, std::string>>{
             {" --labels " + dir.file("seg.hvo") + " --overlay " + dir.file("ct.hvo"), "one volume at a time"},
             {" --labels " + dir.file("seg.hvo") + " --mode mip", "in DVR only"},
             {" --labels " + dir.file("ct.hvo"), "is not a label map"},
             {" --lut " + dir.file("seg.hvo.ctbl"), "go with --labels"}}) {
        r = test::runCommand(cli + " lightfield " + dir.file("ct.hvo") + args + " --display looking-glass-portrait -o " +
                             dir.file("no") + " 2>&1");
        EXPECT_NE(r.exitCode, 0) << args;
        EXPECT_NE(r.output.find(sentence), std::string::npos) << args << ": " << r.output;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("no_qs8x6a0.75.png")));
}

// render --time N: the N-th time point of pydicom's ten-time-point series, from the database
// (built on first use, then reused); time points and inputs that are not 4D are refused.
TEST(CliGlCommands, RenderDrawsATimePointOfA4DSeries) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand("/usr/bin/python3 " HVX_SOURCE_DIR "/tests/support/dicom_cases.py " + dir.file("cases")).exitCode, 0);
    const std::string db = " --db " + dir.file("s.db");
    auto r = test::runCommand(cli + " import " + dir.file("cases/dynamic") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " studies" + db);
    const auto at = r.output.find("    series ");
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::string line = r.output.substr(at, r.output.find('\n', at) - at);
    const std::string uid = line.substr(line.rfind(' ') + 1);
    r = test::runCommand(cli + " render " + uid + db + " --time 3 --size 64x64 -o " + dir.file("t3.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("time point 3 of 10: time 3"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("built its octree"), std::string::npos) << r.output;
    EXPECT_TRUE(std::filesystem::exists(dir.file("t3.png")));
    r = test::runCommand(cli + " render " + uid + db + " --time 3 --size 64x64 -o " + dir.file("again.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("built its octree"), std::string::npos) << "the recorded octree was not reused: " << r.output;
    for (const auto& [args, sentence] : std::vector<std::pair<std::string, std::string>>{
             {uid + db + " --time 11", "--time"},
             {dir.file("t.hvo") + " --time 2", "give the series' UID"},
             {"1.2.3.4" + db + " --time 2", "is not in the database"}}) {
        r = test::runCommand(cli + " render " + args + " -o " + dir.file("no.png") + " 2>&1");
        EXPECT_NE(r.exitCode, 0) << args;
        EXPECT_NE(r.output.find(sentence), std::string::npos) << args << ": " << r.output;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("no.png")));
}

// The light field's default framing: what shows fills each tile's width (a Looking Glass user's
// expectation), its depth compressed into the range the display shows sharply; with
// --true-depth the same scale both ways, and the volume is far smaller (what it was before).
TEST(CliGlCommands, LightFieldFillsTheScreensWidth) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand(cli + " phantom --size 32x32x32 -o " + dir.file("p.hvo")).exitCode, 0);
    const std::string spans =
        "/usr/bin/python3 -c \"import sys; from vtkmodules.vtkIOImage import vtkPNGReader; "
        "from vtkmodules.util.numpy_support import vtk_to_numpy; "
        "r = vtkPNGReader(); r.SetFileName(sys.argv[1]); r.Update(); w, h, _ = r.GetOutput().GetDimensions(); "
        "a = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(h, w, -1)[::-1, :, :3].max(axis=2); "
        "tw, th = w // 8, h // 6; "
        "print(min(int((a[i * th:(i + 1) * th, j * tw:(j + 1) * tw] > 8).any(axis=0).sum()) for i in range(6) for j in range(8)), tw)\" ";
    for (const bool trueDepth : {false, true}) {
        const std::string out = dir.file(trueDepth ? "t" : "q");
        auto r = test::runCommand(cli + " lightfield " + dir.file("p.hvo") + " --display looking-glass-portrait --size 60x80 " +
                                  "--mode mip -o " + out + (trueDepth ? " --true-depth" : ""));
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find(trueDepth ? "(true depth;" : "(compressed to fit it;"), std::string::npos) << r.output;
        const auto s = test::runCommand(spans + out + "_qs8x6a0.75.png");
        int narrowest = 0, tile = 0;
        ASSERT_EQ(std::sscanf(s.output.c_str(), "%d %d", &narrowest, &tile), 2) << s.output;
        std::printf("%s: the narrowest of 48 tiles shows the volume across %d of %d columns\n",
                    trueDepth ? "true depth" : "default", narrowest, tile);
        if (trueDepth) EXPECT_LT(narrowest, tile / 2);
        else EXPECT_GE(narrowest, tile * 8 / 10);
    }
}
