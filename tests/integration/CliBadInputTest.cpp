#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string cli = HVX_CLI;

// Every bad input: non-zero exit, exactly one line on the terminal naming `mustName` (after
// the input's own warnings, such as a raw file's unknown orientation), and nothing left in the
// output directory but the inputs.
void expectCleanFailure(const std::string& args, const test::TempDir& dir, const std::string& mustName,
                        const std::vector<std::string>& inputsLeft, const std::string& reason = "") {
    const auto r = test::runCommand(cli + " " + args + " 2>&1");
    EXPECT_NE(r.exitCode, 0) << r.output;
    std::size_t lines = 0;
    for (std::size_t at = 0, end; (end = r.output.find('\n', at)) != std::string::npos; at = end + 1)
        lines += r.output.compare(at, 21, "holovox-cli: warning:") != 0;
    EXPECT_EQ(lines, 1u) << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(mustName), std::string::npos) << r.output;
    if (!reason.empty()) EXPECT_NE(r.output.find(reason), std::string::npos) << r.output;
    EXPECT_EQ(dir.entries(), inputsLeft) << "after: " << args;
}

void writeBytes(const std::string& path, std::size_t n) {
    std::ofstream f(path, std::ios::binary);
    f << std::string(n, '\x01');
}
}  // namespace

TEST(CliBadInput, DimensionsThatDoNotMatchTheFileSize) {
    test::TempDir dir;
    writeBytes(dir.file("v.raw"), 1000);
    expectCleanFailure("build " + dir.file("v.raw") + " --dims 10x10x10 --type int16 -o " + dir.file("o.hvo"), dir,
                       dir.file("v.raw"), {"v.raw"}, "need 2000 bytes but the file has 1000");
}

TEST(CliBadInput, TruncatedNrrdInput) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand(cli + " phantom --size 16x16x16 -o " + dir.file("p.nrrd")).exitCode, 0);
    std::filesystem::resize_file(dir.file("p.nrrd"), std::filesystem::file_size(dir.file("p.nrrd")) - 100);
    expectCleanFailure("build " + dir.file("p.nrrd") + " -o " + dir.file("o.hvo"), dir, dir.file("p.nrrd"),
                       {"p.nrrd"}, "bytes but the file has");
}

TEST(CliBadInput, TruncatedNiftiInput) {
    test::TempDir dir;
    const auto r = test::runCommand("gzip -dc /usr/share/mricron/templates/ch2better.nii.gz | head -c 2000000 > " +
                                    dir.file("t.nii"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectCleanFailure("build " + dir.file("t.nii") + " -o " + dir.file("o.hvo"), dir, dir.file("t.nii"), {"t.nii"});
}

TEST(CliBadInput, UnsupportedScalarType) {
    test::TempDir dir;
    writeBytes(dir.file("v.raw"), 4000);
    expectCleanFailure("build " + dir.file("v.raw") + " --dims 10x10x10 --type complex64 -o " + dir.file("o.hvo"), dir,
                       "complex64", {"v.raw"}, "unsupported");
    {
        std::ofstream f(dir.file("d.nrrd"));
        f << "NRRD0004\ntype: block\nblock size: 8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" << std::string(64, '\0');
    }
    expectCleanFailure("build " + dir.file("d.nrrd") + " -o " + dir.file("o.hvo"), dir, dir.file("d.nrrd"),
                       {"d.nrrd", "v.raw"}, "unsupported NRRD type");
}

TEST(CliBadInput, OutputThatCannotBeWritten) {
    test::TempDir dir;
    expectCleanFailure("phantom --size 8x8x8 -o " + dir.file("missing/dir/o.hvo"), dir, dir.file("missing/dir/o.hvo"),
                       {}, "cannot write output");
    expectCleanFailure("phantom --size 8x8x8 -o /proc/holovox.hvo", dir, "/proc/holovox.hvo", {});
}

TEST(CliBadInput, FullDiskLeavesNoPartialOutput) {
    // The file-size limit makes write() fail with EFBIG exactly as a full disk fails with ENOSPC.
    test::TempDir dir;
    const auto r = test::runCommand("ulimit -f 64; " + cli + " phantom --size 64x64x64 -o " + dir.file("o.hvo") + " 2>&1");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find(dir.file("o.hvo")), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("disk full"), std::string::npos) << r.output;
    EXPECT_TRUE(dir.entries().empty());
}

TEST(CliBadInput, BadOptionsAndUsage) {
    test::TempDir dir;
    expectCleanFailure("phantom --size 0x8x8 -o " + dir.file("o.hvo"), dir, "0x8x8", {});
    expectCleanFailure("build phantom:8x8x8 --brick 3 -o " + dir.file("o.hvo"), dir, "--brick", {});
    expectCleanFailure("build phantom:8x8x8 --codec brotli -o " + dir.file("o.hvo"), dir, "brotli", {});
    expectCleanFailure("build phantom:8x8x8 --frobnicate -o " + dir.file("o.hvo"), dir, "--frobnicate", {});
    expectCleanFailure("info " + dir.file("none.hvo"), dir, dir.file("none.hvo"), {});
}

// COMMAND --help and -h print that command's usage (and only its lines) and exit 0 without
// running it (demo --help starts no archive, listen --help opens no port); an unknown command's
// help is an error.
TEST(CliBadInput, EveryCommandHasItsOwnHelp) {
    test::TempDir dir;
    for (const std::string cmd : {"build", "info", "phantom", "demo", "import", "studies", "prune", "build-series",
                                  "export-dicom", "pacs", "listen", "dicom-info", "render", "lightfield", "measure",
                                  "label-stats", "slice", "gl-info", "version"})
        for (const char* help : {"--help", "-h"}) {
            const auto r = test::runCommand("cd " + dir.path().string() + " && " + cli + " " + cmd + " " + help + " 2>&1");
            EXPECT_EQ(r.exitCode, 0) << cmd << " " << help << ": " << r.output;
            EXPECT_EQ(r.output.rfind("usage: holovox-cli\n  " + cmd, 0), 0u) << cmd << ": " << r.output;
            EXPECT_EQ(r.output.find("  render "), cmd == "render" ? r.output.find("  render ") : std::string::npos)
                << cmd << ": another command's usage too";
        }
    const auto sub = test::runCommand(cli + " pacs get --help 2>&1");
    EXPECT_EQ(sub.exitCode, 0);
    EXPECT_NE(sub.output.find("pacs get|move NODE STUDY_UID"), std::string::npos) << sub.output;
    EXPECT_TRUE(dir.entries().empty()) << "a command ran";
    const auto unknown = test::runCommand(cli + " frobnicate --help 2>&1");
    EXPECT_EQ(unknown.exitCode, 2);
    EXPECT_NE(unknown.output.find("unknown command 'frobnicate'"), std::string::npos) << unknown.output;
}

TEST(CliBadInput, LightFieldAndToolInputsFailCleanlyBeforeRendering) {
    test::TempDir dir;
    ASSERT_EQ(test::runCommand(cli + " phantom --size 32x32x24 -o " + dir.file("p.hvo") + " --quiet").exitCode, 0);
    expectCleanFailure("lightfield " + dir.file("p.hvo") + " --display no-such-display -o " + dir.file("out"), dir,
                       "no-such-display", {"p.hvo"}, "neither a built-in profile");
    expectCleanFailure("lightfield " + dir.file("p.hvo") + " --display holovizio-96 --format quilt -o " + dir.file("out"),
                       dir, "quilt", {"p.hvo"}, "needs a lenticular display");
    expectCleanFailure("lightfield " + dir.file("p.hvo") + " --display holovizio-96 --format gif -o " + dir.file("out"), dir,
                       "--format", {"p.hvo"});
    // Outputs that cannot be written fail before the first ray (rendering can take minutes).
    expectCleanFailure("lightfield " + dir.file("p.hvo") + " --display looking-glass-portrait --size 8x10 --cpu -o " +
                           dir.file("missing/q"),
                       dir, "missing", {"p.hvo"}, "does not exist");
    expectCleanFailure("lightfield " + dir.file("p.hvo") + " --display holovizio-96 --size 8x6 --cpu --format projectors -o " +
                           dir.file("p.hvo/views"),
                       dir, "p.hvo/views", {"p.hvo"}, "cannot make the output folder");
    expectCleanFailure("lightfield " + dir.file("p.hvo") + " --display holovizio-96 --size 8x6 --cpu -o " + dir.file("v") +
                           " --observer 0,0,1000 --simulate " + dir.file("gone/seen.png"),
                       dir, "gone", {"p.hvo"}, "does not exist");  // nor is the projectors' folder made
    std::ofstream(dir.file("tools.json")) << R"({"mimda": {"enabled": true, "gamma": 3}})";
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --tools " + dir.file("tools.json") + " -o " + dir.file("o.png"),
                       dir, "tools.json", {"p.hvo", "tools.json"}, "gamma must be between 0 and 1");
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --gradient-opacity 10:0,50 -o " + dir.file("o.png"), dir,
                       "--gradient-opacity", {"p.hvo", "tools.json"}, "GRADIENT:SCALE pairs");
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --gradient-opacity 10:0,50:2 -o " + dir.file("o.png"), dir,
                       "gradient opacity", {"p.hvo", "tools.json"}, "scale of 0 to 1");
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --unsharp 9 -o " + dir.file("o.png"), dir, "--unsharp",
                       {"p.hvo", "tools.json"}, "between 0 and 8");
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --exaggerated 1.5 -o " + dir.file("o.png"), dir,
                       "--exaggerated", {"p.hvo", "tools.json"}, "between 0 and 1");
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --multilevel --nearest -o " + dir.file("o.png"), dir,
                       "--multilevel", {"p.hvo", "tools.json"}, "not with --nearest");
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --refraction 5 -o " + dir.file("o.png"), dir, "refraction index",
                       {"p.hvo", "tools.json"}, "between 0.25 and 4");
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --refraction 0:1,100 -o " + dir.file("o.png"), dir,
                       "--refraction", {"p.hvo", "tools.json"}, "VALUE:INDEX pairs");
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --refraction 1.3 --mode mip -o " + dir.file("o.png"), dir,
                       "--refraction", {"p.hvo", "tools.json"}, "--mode other than dvr");
    std::ofstream(dir.file("clip.json")) << R"({"clip": {"enabled": true}})";
    expectCleanFailure("render " + dir.file("p.hvo") + " --cpu --refraction 1.3 --tools " + dir.file("clip.json") + " -o " +
                           dir.file("o.png"),
                       dir, "--refraction", {"clip.json", "p.hvo", "tools.json"}, "--tools");
    std::filesystem::remove(dir.file("clip.json"));
    std::ofstream(dir.file("fix.json")) << R"({"projectors": [{"lut": {"r": [2]}}]})";
    expectCleanFailure("lightfield " + dir.file("p.hvo") + " --display stereo-anaglyph --size 16x12 --cpu --correction " +
                           dir.file("fix.json") + " -o " + dir.file("s.png"),
                       dir, "fix.json", {"fix.json", "p.hvo", "tools.json"});
    // A good quilt: the file named by the convention and its layout beside it, nothing else.
    const auto r = test::runCommand(cli + " lightfield " + dir.file("p.hvo") +
                                    " --display looking-glass-portrait --size 8x10 --cpu -o " + dir.file("q") + " 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(dir.entries(),
              (std::vector<std::string>{"fix.json", "p.hvo", "q_qs8x6a0.75.json", "q_qs8x6a0.75.png", "tools.json"}));
}

// Split-voxel builds: parameters out of range, split options without --split-voxels, a float
// volume, and a split-voxel octree given to a command that draws voxels, each refused in one
// sentence that names what is wrong, leaving nothing behind.
TEST(CliBadInput, SplitVoxelParametersAndFilesAreRefusedInWords) {
    test::TempDir dir;
    const std::string out = " -o " + dir.file("s.hvo");
    expectCleanFailure("build phantom:16x16x16 --split-voxels --split-n 1" + out, dir, "--split-n 1", {}, "out of range");
    expectCleanFailure("build phantom:16x16x16 --split-voxels --split-n 9" + out, dir, "--split-n 9", {}, "out of range");
    expectCleanFailure("build phantom:16x16x16 --split-voxels --split-overlap 5" + out, dir, "--split-overlap 5", {},
                       "out of range");
    expectCleanFailure("build phantom:16x16x16 --split-voxels --split-threshold -5" + out, dir, "--split-threshold", {});
    expectCleanFailure("build phantom:16x16x16 --split-n 4" + out, dir, "--split-voxels", {});
    expectCleanFailure("build phantom:16x16x16 --split-voxels --lossy8" + out, dir, "--lossy8", {});
    writeBytes(dir.file("f.raw"), 16 * 16 * 16 * 4);
    expectCleanFailure("build " + dir.file("f.raw") + " --dims 16x16x16 --type float32 --split-voxels" + out, dir,
                       "8- or 16-bit integer", {"f.raw"});
    ASSERT_EQ(test::runCommand(cli + " build phantom:16x16x16 --split-voxels --quiet" + out).exitCode, 0);
    expectCleanFailure("render " + dir.file("s.hvo") + " --mode iso -o " + dir.file("x.png"), dir, "split-voxel octree",
                       {"f.raw", "s.hvo"}, "DVR");
    expectCleanFailure("render " + dir.file("s.hvo") + " --cpu --mode mip -o " + dir.file("x.png"), dir, "s.hvo",
                       {"f.raw", "s.hvo"}, "DVR");
    expectCleanFailure("slice " + dir.file("s.hvo") + " -o " + dir.file("x.png"), dir, "split-voxel octree",
                       {"f.raw", "s.hvo"});
    // A split-voxel octree is no volume to build from; a lossy octree's values are not the volume's.
    expectCleanFailure("build " + dir.file("s.hvo") + " --split-voxels -o " + dir.file("t.hvo"), dir, "split-voxel octree",
                       {"f.raw", "s.hvo"});
    ASSERT_EQ(test::runCommand(cli + " build phantom:16x16x16 --lossy8 --quiet -o " + dir.file("l.hvo")).exitCode, 0);
    expectCleanFailure("build " + dir.file("l.hvo") + " --split-voxels -o " + dir.file("t.hvo"), dir, "l.hvo",
                       {"f.raw", "l.hvo", "s.hvo"}, "lossily");
    std::filesystem::remove(dir.file("l.hvo"));
    // The CPU reference draws it.
    const auto r = test::runCommand(cli + " render " + dir.file("s.hvo") + " --cpu --size 64x64 -o " + dir.file("x.png"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"f.raw", "s.hvo", "x.png"}));
}
