// Removing a study when a received file cannot be deleted: the file is named, indexed again
// (the study stays listed with it, nothing left in the storage folder unknown to the index), and
// removing the study again once the file can be deleted finishes the job.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/IncomingStore.h"
#include "dicom/StudyDatabase.h"
#include "dicom/StudyRemoval.h"
#include "tests/support/TempDir.h"

using namespace hvx;
namespace fs = std::filesystem;

namespace {
const std::string ctSmall = "/usr/lib/python3/dist-packages/pydicom/data/test_files/CT_small.dcm";

/// Makes a file impossible to delete while it lives: marked immutable (as root, on a file system
/// that has the flag), else its folder made read-only (as anyone else). ok() is false where
/// neither holds, and the test is skipped.
class Undeletable {
public:
    explicit Undeletable(const std::string& path) : path_(path), folder_(fs::path(path).parent_path().string()) {
        if (setImmutable(true)) {
            immutable_ = true;
        } else if (::chmod(folder_.c_str(), 0555) == 0) {
            readOnly_ = true;
        }
        if (immutable_) {
            ok_ = ::unlink(path_.c_str()) != 0;
        } else if (readOnly_) {  // (root writes into a read-only folder all the same)
            const std::string probe = folder_ + "/probe";
            ok_ = !std::ofstream(probe).good();
            if (!ok_) std::remove(probe.c_str());
        }
    }
    ~Undeletable() { undo(); }
    Undeletable(const Undeletable&) = delete;
    Undeletable& operator=(const Undeletable&) = delete;
    bool ok() const { return ok_; }
    void undo() {
        if (immutable_) setImmutable(false);
        if (readOnly_) ::chmod(folder_.c_str(), 0755);
        immutable_ = readOnly_ = false;
    }

private:
    bool setImmutable(bool on) {
        const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return false;
        int flags = 0;
        bool done = ::ioctl(fd, FS_IOC_GETFLAGS, &flags) == 0;
        flags = on ? flags | FS_IMMUTABLE_FL : flags & ~FS_IMMUTABLE_FL;
        done = done && ::ioctl(fd, FS_IOC_SETFLAGS, &flags) == 0;
        ::close(fd);
        return done;
    }
    std::string path_, folder_;
    bool immutable_ = false, readOnly_ = false, ok_ = false;
};
}  // namespace

TEST(StudyRemoval, AReceivedFileThatCannotBeDeletedIsIndexedAgainAndRemovedNextTime) {
    test::TempDir dir;
    const std::string storage = dir.file("storage"), octrees = dir.file("octrees");
    fs::create_directories(octrees);
    dicom::IncomingStore store(storage);
    const std::string temporary = store.temporaryPath();
    fs::copy_file(ctSmall, temporary, fs::copy_options::overwrite_existing);
    const dicom::DicomInstance in = store.finalize(temporary);
    dicom::StudyDatabase db(dir.file("s.sqlite"));
    ASSERT_EQ(db.addInstances({in}).added, 1u);

    Undeletable stuck(in.path);
    if (!stuck.ok()) GTEST_SKIP() << "cannot make a file undeletable here (no immutable flag, and root ignores modes)";
    const auto r = dicom::StudyRemoval::remove(db, in.studyInstanceUid, storage, octrees);
    EXPECT_EQ(r.forgotten, 1u);
    EXPECT_EQ(r.deleted, 0u);
    ASSERT_EQ(r.failed.size(), 1u);
    EXPECT_NE(r.failed[0].find(in.path), std::string::npos) << r.failed[0];
    EXPECT_EQ(r.reindexed, 1u);
    EXPECT_TRUE(fs::exists(in.path));
    EXPECT_EQ(db.filesOfSeries(in.seriesInstanceUid), std::vector<std::string>{in.path})
        << "the file stayed in the storage folder unknown to the index";

    stuck.undo();
    const auto again = dicom::StudyRemoval::remove(db, in.studyInstanceUid, storage, octrees);
    EXPECT_EQ(again.deleted, 1u);
    EXPECT_TRUE(again.failed.empty());
    EXPECT_EQ(again.reindexed, 0u);
    EXPECT_FALSE(fs::exists(in.path));
    EXPECT_FALSE(fs::exists(fs::path(in.path).parent_path())) << "the emptied series folder stays";
    EXPECT_TRUE(db.filesOfSeries(in.seriesInstanceUid).empty());
    EXPECT_THROW(dicom::StudyRemoval::remove(db, in.studyInstanceUid, storage, octrees), core::Error);
}
