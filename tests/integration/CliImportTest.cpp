#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "dicom/IncomingStore.h"
#include "dicom/UidPath.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string cli = HVX_CLI;
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
}  // namespace

TEST(CliImport, ImportPrintsTheTableBuildsOctreesAndIsIdempotent) {
    test::TempDir dir;
    const std::string db = " --db " + dir.file("db.sqlite");
    ASSERT_EQ(test::runCommand(cli + " phantom --size 48x40x24 -o " + dir.file("p.nrrd")).exitCode, 0);
    auto r = test::runCommand(cli + " export-dicom " + dir.file("p.nrrd") + " -o " + dir.file("dcm/ct") +
                              " --patient DOE^JOHN --patient-id PID42 --study 'CT THORAX' --date 20240301");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::filesystem::copy_file("/usr/lib/python3/dist-packages/pydicom/data/test_files/CT_small.dcm",
                               dir.file("dcm/CT_small.dcm"));
    std::ofstream(dir.file("dcm/readme.txt")) << "not DICOM";
    r = test::runCommand(cli + " import " + dir.file("dcm") + db + " --build");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "scanned 26 files: 25 DICOM, 1 not DICOM (skipped), 0 broken")) << r.output;
    EXPECT_TRUE(contains(r.output, "25 new")) << r.output;
    EXPECT_TRUE(contains(r.output, "patient DOE^JOHN (PID42)")) << r.output;
    EXPECT_TRUE(contains(r.output, "study 20240301")) << r.output;
    EXPECT_TRUE(contains(r.output, "48 x   40 x   24")) << r.output;
    EXPECT_TRUE(contains(r.output, "built ")) << r.output;

    r = test::runCommand(cli + " import " + dir.file("dcm") + db);
    EXPECT_TRUE(contains(r.output, "0 new, 25 already known")) << r.output;

    r = test::runCommand(cli + " studies" + db + " --patient 'doe*'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "CT THORAX")) << r.output;
    EXPECT_TRUE(contains(r.output, "24 images")) << r.output;
    EXPECT_TRUE(contains(r.output, "octree: ")) << r.output;
    EXPECT_TRUE(contains(r.output, "1 studies")) << r.output;
    r = test::runCommand(cli + " studies" + db + " --from 20240101 --to 20241231 --modality MR");
    EXPECT_TRUE(contains(r.output, "0 studies")) << r.output;

    // Deleting files is noticed, and rows are removed only by prune.
    std::filesystem::remove(dir.file("dcm/CT_small.dcm"));
    r = test::runCommand(cli + " studies" + db);
    EXPECT_TRUE(contains(r.output, "1 instances are offline")) << r.output;
    EXPECT_TRUE(contains(r.output, "2 studies")) << r.output;
    r = test::runCommand(cli + " prune" + db);
    EXPECT_TRUE(contains(r.output, "removed 1 instances whose files were deleted")) << r.output;
    r = test::runCommand(cli + " studies" + db);
    EXPECT_TRUE(contains(r.output, "1 studies")) << r.output;

    // The folder renamed away (an unmounted disk): nothing is deleted, even by prune.
    std::filesystem::rename(dir.file("dcm"), dir.file("away"));
    r = test::runCommand(cli + " studies" + db);
    EXPECT_TRUE(contains(r.output, "24 instances are offline")) << r.output;
    EXPECT_TRUE(contains(r.output, "1 studies")) << r.output;
    r = test::runCommand(cli + " prune" + db);
    EXPECT_TRUE(contains(r.output, "kept 24 instances whose folders are missing")) << r.output;
    std::filesystem::rename(dir.file("away"), dir.file("dcm"));
    r = test::runCommand(cli + " studies" + db);
    EXPECT_TRUE(contains(r.output, "24 instances are back online")) << r.output;
    EXPECT_TRUE(contains(r.output, "24 images")) << r.output;
}

TEST(CliImport, BuildSeriesFromTheDatabase) {
    test::TempDir dir;
    const std::string db = " --db " + dir.file("db.sqlite");
    ASSERT_EQ(test::runCommand(cli + " phantom --size 32x32x16 -o " + dir.file("p.nrrd")).exitCode, 0);
    ASSERT_EQ(test::runCommand(cli + " export-dicom " + dir.file("p.nrrd") + " -o " + dir.file("s") +
                               " --syntax jpeg-ls").exitCode, 0);
    auto r = test::runCommand(cli + " import " + dir.file("s") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " studies" + db);
    const auto at = r.output.find("images  ");
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::string uid = r.output.substr(at + 8, r.output.find_first_of(" \n", at + 8) - at - 8);
    r = test::runCommand(cli + " build-series " + uid + db + " -o " + dir.file("s.hvo"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "32 x 32 x 16 int16")) << r.output;
    r = test::runCommand(cli + " build-series 1.2.3.4.5" + db + " -o " + dir.file("t.hvo") + " 2>&1");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_TRUE(contains(r.output, "series 1.2.3.4.5 is not in the database")) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("t.hvo")));
}

TEST(CliImport, BrokenFilesAreCountedWithReasonsAndMissingPathsRefused) {
    test::TempDir dir;
    std::filesystem::create_directories(dir.file("in"));
    std::ifstream in("/usr/lib/python3/dist-packages/pydicom/data/test_files/CT_small.dcm", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir.file("in/cut.dcm"), std::ios::binary) << all.substr(0, 700);
    auto r = test::runCommand(cli + " import " + dir.file("in") + " --db " + dir.file("db.sqlite"));
    EXPECT_TRUE(contains(r.output, "1 broken")) << r.output;
    EXPECT_TRUE(contains(r.output, "broken: " + dir.file("in/cut.dcm"))) << r.output;
    r = test::runCommand(cli + " import " + dir.file("nowhere") + " --db " + dir.file("db.sqlite") + " 2>&1");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_TRUE(contains(r.output, dir.file("nowhere") + ": no such file or folder")) << r.output;
}

namespace {
/// Runs a pydicom script (Debian's python3) that writes its files into dir/in (its argv[1]).
test::ProcessResult writeWithPydicom(const test::TempDir& dir, const std::string& script) {
    std::ofstream(dir.file("make.py")) << script;
    std::filesystem::create_directory(dir.file("in"));
    return test::runCommand("/usr/bin/python3 " + dir.file("make.py") + " " + dir.file("in"));
}
}  // namespace

// A small file that claims 2^31 - 1 frames (with a per-frame sequence, as RT dose, and as
// encapsulated RLE) must be refused at once, in little memory, never sized from the claim.
TEST(CliImport, HostileFrameCountIsRefusedQuicklyInLittleMemory) {
    test::TempDir dir;
    const std::string script = R"(
import sys, pydicom
from pydicom.dataset import Dataset
from pydicom.sequence import Sequence
src = '/usr/lib/python3/dist-packages/pydicom/data/test_files/'
out = sys.argv[1]
ds = pydicom.dcmread(src + 'CT_small.dcm')
ds.NumberOfFrames = 2147483647
ds.PerFrameFunctionalGroupsSequence = Sequence([Dataset()])
ds.save_as(out + '/perframe.dcm')
ds = pydicom.dcmread(src + 'CT_small.dcm')
ds.NumberOfFrames = 2147483647
ds.GridFrameOffsetVector = [0, 1]
ds.save_as(out + '/dose.dcm')
ds = pydicom.dcmread(src + 'MR_small_RLE.dcm')
ds.NumberOfFrames = 2147483647
ds.save_as(out + '/rle.dcm')
)";
    auto r = writeWithPydicom(dir, script);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto start = std::chrono::steady_clock::now();
    r = test::runCommand(cli + " import " + dir.file("in") + " --db " + dir.file("db.sqlite"));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(contains(r.output, "3 broken")) << r.output;
    EXPECT_TRUE(contains(r.output, "NumberOfFrames 2147483647 cannot be right")) << r.output;
    EXPECT_EQ(r.exitCode, 1) << "nothing was imported";
    EXPECT_LT(seconds, 1.0) << "the CLI's start and the database are in this time too (measured 0.07 s)";
#ifndef HVX_SANITIZED  // shadow memory: the ci preset checks this bound
    EXPECT_LT(r.maxRssKiB, 100 * 1024) << "peak memory of the import";
#endif
}

// RLE and JPEG 2000 files whose Rows and Columns claim 65535 × 65535 (8 GiB a frame) over a
// few kilobytes of stream: indexed (the header is readable), refused by the build at once.
TEST(CliImport, HostileRowsAndColumnsInCompressedFramesAreRefusedBeforeDecoding) {
    test::TempDir dir;
    const std::string script = R"(
import sys, pydicom
src = '/usr/lib/python3/dist-packages/pydicom/data/test_files/'
for name, out in (('MR_small_RLE.dcm', 'rle'), ('MR_small_jp2klossless.dcm', 'j2k')):
    ds = pydicom.dcmread(src + name)
    ds.Rows = 65535
    ds.Columns = 65535
    ds.SeriesInstanceUID = ds.SeriesInstanceUID + '.' + str(len(out))
    ds.SOPInstanceUID = ds.SOPInstanceUID + '.' + str(len(out))
    ds.save_as(sys.argv[1] + '/' + out + '.dcm')
)";
    auto r = writeWithPydicom(dir, script);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto start = std::chrono::steady_clock::now();
    r = test::runCommand(cli + " import " + dir.file("in") + " --db " + dir.file("db.sqlite") + " --build 2>&1");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "65535 × 65535 pixels cannot be right")) << r.output;
    EXPECT_LT(seconds, 2.0);
#ifndef HVX_SANITIZED  // shadow memory: the ci preset checks this bound
    EXPECT_LT(r.maxRssKiB, 100 * 1024) << "peak memory of the import";
#endif
}

// A study whose patient the archive has corrected since (the same Study Instance UID, another
// Patient ID) is refused as a collision, and the refusal says how to go on: remove-study forgets
// the local study, deletes the files Holovox received into its storage folder and the octrees
// it built, and never deletes a file imported from the user's own folders. The corrected study
// then imports. The patient ID is changed by DCMTK's dcmodify, and the study UID read by dcmdump.
TEST(CliImport, RemoveStudyForgetsItDeletesOnlyHolovoxsOwnFilesAndLetsTheCorrectedStudyIn) {
    test::TempDir dir;
    const std::string db = " --db " + dir.file("db/studies.sqlite");
    ASSERT_EQ(test::runCommand(cli + " phantom --size 24x20x8 -o " + dir.file("p.nrrd")).exitCode, 0);
    auto r = test::runCommand(cli + " export-dicom " + dir.file("p.nrrd") + " -o " + dir.file("mine/a") +
                              " --patient DOE^ANN --patient-id P1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " export-dicom " + dir.file("p.nrrd") + " -o " + dir.file("sent") +
                         " --patient ROE^BOB --patient-id P2");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // Received as a retrieve receives: through the IncomingStore, into <storage>/<study>/<series>.
    dicom::IncomingStore store(dir.file("storage"));
    for (const auto& e : std::filesystem::directory_iterator(dir.file("sent"))) {
        const std::string part = store.temporaryPath();
        std::filesystem::copy_file(e.path(), part, std::filesystem::copy_options::overwrite_existing);
        store.finalize(part);
    }
    auto studyOf = [&](const std::string& file) {
        const auto d = test::runCommand("dcmdump +P StudyInstanceUID " + file);
        const auto open = d.output.find('['), close = d.output.find(']');
        return d.output.substr(open + 1, close - open - 1);
    };
    const std::string mine = studyOf(dir.file("mine/a/IMG00001.dcm")), received = studyOf(dir.file("sent/IMG00001.dcm"));
    ASSERT_FALSE(mine.empty());
    ASSERT_NE(mine, received);
    ASSERT_EQ(test::runCommand(cli + " import " + dir.file("mine") + db + " --build").exitCode, 0);
    ASSERT_EQ(test::runCommand(cli + " import " + dir.file("storage") + db + " --build").exitCode, 0);
    std::filesystem::copy(dir.file("sent"), dir.file("corrected"));
    ASSERT_EQ(test::runCommand("dcmodify -nb -m '(0010,0020)=P9' " + dir.file("corrected") + "/*.dcm").exitCode, 0);
    r = test::runCommand(cli + " import " + dir.file("corrected") + db);
    EXPECT_TRUE(contains(r.output, "is filed under patient ROE^BOB (P2)")) << r.output;
    EXPECT_TRUE(contains(r.output, "holovox-cli remove-study " + received)) << r.output;
    const auto octrees = [&] {
        std::size_t n = 0;
        for (const auto& e : std::filesystem::directory_iterator(dir.file("db/octrees"))) n += e.path().extension() == ".hvo";
        return n;
    };
    ASSERT_EQ(octrees(), 2u);

    r = test::runCommand(cli + " remove-study " + received + db + " --storage " + dir.file("storage"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "removed study " + received + " of ROE^BOB (P2) from the study database: 8 image(s)")) << r.output;
    EXPECT_TRUE(contains(r.output, "deleted 8 received file(s)")) << r.output;
    EXPECT_TRUE(contains(r.output, "deleted 1 octree(s)")) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("storage/" + dicom::UidPath::component(received))));  // emptied, and gone
    EXPECT_TRUE(std::filesystem::is_directory(dir.file("storage")));
    EXPECT_EQ(octrees(), 1u);

    r = test::runCommand(cli + " remove-study " + mine + db + " --storage " + dir.file("storage"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "kept 8 imported file(s) where they are")) << r.output;
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.file("mine/a")), {}), 8);
    EXPECT_EQ(octrees(), 0u);

    r = test::runCommand(cli + " remove-study " + mine + db);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_TRUE(contains(r.output, "study " + mine + " is not in the study database")) << r.output;
    r = test::runCommand(cli + " import " + dir.file("corrected") + db);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "8 new")) << r.output;
    EXPECT_TRUE(contains(r.output, "patient ROE^BOB (P9)")) << r.output;
}
