// The storage receiver at the edge of its resources: a disk below the free-space floor, a disk
// that really fills up (a small tmpfs mounted for the test), and an instance larger than the
// cap. Each time the sender is told, nothing half-written stays, and the receiver goes on.
#include <gtest/gtest.h>

#include <filesystem>
#include <chrono>
#include <fstream>
#include <mutex>
#include <thread>

#include "core/volume/PhantomVoxelSource.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomSeriesWriter.h"
#include "tests/support/StorageListener.h"

using namespace hvx;

namespace {
/// How storescu -v names status A700.
const std::string kOutOfResources = "Refused: OutOfResources";

std::vector<std::string> phantomSeries(const std::string& dir, std::uint32_t edge, std::uint32_t slices) {
    core::PhantomVoxelSource p({edge, edge, slices}, 4);
    core::JobContext job;
    return dicom::DicomSeriesWriter::write(p, dir, {}, job);
}

/// Regular files under `dir` whose name ends with `suffix` ("" for all).
std::size_t filesUnder(const std::string& dir, const std::string& suffix = "") {
    std::size_t n = 0;
    std::error_code ec;
    for (const auto& f : std::filesystem::recursive_directory_iterator(dir, ec)) {
        const std::string name = f.path().filename().string();
        n += f.is_regular_file() && name.size() >= suffix.size() &&
             name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    }
    return n;
}

/// A line of /proc/self/status ("VmSize", "Threads"), in its own unit.
long procStatus(const std::string& key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));
    return -1;
}

std::string bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A tmpfs of `kib` KiB mounted on `dir` for the life of the object (the test needs the right
/// to mount: root, as in CI's container).
struct SmallDisk {
    std::string dir;
    bool mounted = false;
    std::string why;
    SmallDisk(const std::string& d, int kib) : dir(d) {
        std::filesystem::create_directories(dir);
        const auto r = test::runCommand("mount -t tmpfs -o size=" + std::to_string(kib) + "k tmpfs " + dir + " 2>&1");
        mounted = r.exitCode == 0;
        why = r.output;
    }
    ~SmallDisk() {
        if (mounted) test::runCommand("umount " + dir);
    }
};
}  // namespace

TEST(StorageLimits, BelowTheFreeSpaceFloorEveryInstanceIsRefusedAsOutOfResources) {
    test::StorageListener l([](dicom::LocalNode& n) { n.minFreeBytes = std::uint64_t(1) << 60; });
    test::TempDir src;
    const auto files = phantomSeries(src.file("s"), 32, 4);
    const std::string out = l.storeVerbose("MODALITY1", files).output;
    // All four are refused in one association: the refusal leaves it usable.
    std::size_t refusals = 0;
    for (std::size_t at = out.find(kOutOfResources); at != std::string::npos; at = out.find(kOutOfResources, at + 1))
        ++refusals;
    EXPECT_EQ(refusals, files.size()) << out;
    EXPECT_EQ(l.server->received(), 0u);
    EXPECT_EQ(filesUnder(l.local.storageDir), 0u) << "nothing may be written below the floor";
    EXPECT_TRUE(l.echoes());
}

TEST(StorageLimits, AFullDiskLosesNoStoredInstanceAndLeavesNoPartialFile) {
    test::TempDir src;
    const auto files = phantomSeries(src.file("s"), 256, 12);  // 12 × 128 KiB of pixels
    test::TempDir mnt;
    SmallDisk disk(mnt.file("disk"), 800);
    if (!disk.mounted) GTEST_SKIP() << "cannot mount a tmpfs here (needs root): " << disk.why;
    {
        test::StorageListener l([&](dicom::LocalNode& n) {
            n.storageDir = disk.dir + "/rx";
            n.minFreeBytes = 0;  // no floor: the disk itself runs out
        });
        const std::string out = l.storeVerbose("MODALITY1", files).output;
        std::lock_guard lock(l.mutex);
        EXPECT_GT(l.server->received(), 0u);
        EXPECT_LT(l.server->received(), files.size()) << "the disk was meant to fill up";
        // The instance that meets the full disk cannot be read to its end: its association is
        // aborted, which the sender reports as a failed store.
        EXPECT_NE(out.find("Store Failed"), std::string::npos)
            << "the sender must learn that not everything was stored: " << out;
        EXPECT_EQ(filesUnder(l.local.storageDir, ".part"), 0u) << "a half-written instance was left";
        EXPECT_EQ(filesUnder(l.local.storageDir, ".dcm"), l.server->received());
        // Every stored instance is whole: the same bytes as the file that was sent.
        for (const auto& in : l.got) {
            bool same = false;
            for (const auto& f : files) same = same || bytesOf(f).substr(bytesOf(f).size() - 4096) ==
                                                           bytesOf(in.path).substr(bytesOf(in.path).size() - 4096);
            EXPECT_TRUE(same) << in.path;
        }
        EXPECT_TRUE(l.echoes()) << "the receiver must go on after a full disk";
    }
    {  // With a floor the same disk refuses before writing anything.
        test::StorageListener l([&](dicom::LocalNode& n) {
            n.storageDir = disk.dir + "/rx2";
            n.minFreeBytes = 512 << 10;
        });
        const std::string out = l.storeVerbose("MODALITY1", {files[0]}).output;
        EXPECT_NE(out.find(kOutOfResources), std::string::npos) << out;
        EXPECT_EQ(l.server->received(), 0u);
    }
}

TEST(StorageLimits, AnInstanceOverTheCapIsCutOffAndTheNextSenderIsServed) {
    test::StorageListener l([](dicom::LocalNode& n) { n.maxInstanceBytes = 64 << 10; });
    test::TempDir src;
    const auto big = phantomSeries(src.file("big"), 256, 1);  // 128 KiB of pixels
    const auto small = phantomSeries(src.file("small"), 32, 2);
    EXPECT_NE(l.store("MODALITY1", big), "");
    EXPECT_EQ(l.server->received(), 0u);
    // The sender may see the abort before the receiver has removed what it had begun writing:
    // give the receiver up to 5 s to clean up (under load, 1 of ~10 runs found the file there).
    for (int i = 0; i < 50 && filesUnder(l.local.storageDir) != 0u; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    EXPECT_EQ(filesUnder(l.local.storageDir), 0u) << "nothing of the oversized instance may stay";
    EXPECT_EQ(l.store("MODALITY1", small), "");
    EXPECT_EQ(l.server->received(), small.size());
}

// Every association's worker thread is joined when it ends: DCMTK's own SCP pool leaves each
// one unjoined, which keeps its stack mapped (8 MiB of address space per association).
TEST(StorageLimits, ManyAssociationsLeaveNoThreadOrStackBehind) {
    test::StorageListener l;
    ASSERT_TRUE(l.echoes());  // the first association's allocations are not growth
    const long threadsBefore = procStatus("Threads");
    const long vmBefore = procStatus("VmSize");
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(l.echoes()) << "association " << i;
    for (int i = 0; i < 50 && procStatus("Threads") > threadsBefore; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the listener reaps each second
    const long grownKiB = procStatus("VmSize") - vmBefore;
    std::printf("60 associations: %+ld KiB of address space, %ld threads before and %ld after\n", grownKiB,
                threadsBefore, procStatus("Threads"));
    EXPECT_LE(procStatus("Threads"), threadsBefore);
    EXPECT_LT(grownKiB, 64 * 1024) << "each association left memory behind";
}
