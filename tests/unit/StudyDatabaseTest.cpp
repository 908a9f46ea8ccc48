#include <gtest/gtest.h>

#include <cstdlib>

#include <filesystem>
#include <fstream>

#include "core/base/Error.h"
#include "dicom/StudyDatabase.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StorageOwners.h"
#include "dicom/StudyRemoval.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
dicom::DicomInstance instance(const std::string& path, const std::string& patient, const std::string& id,
                              const std::string& study, const std::string& date, const std::string& series,
                              const std::string& modality, const std::string& sop) {
    dicom::DicomInstance in;
    in.path = path;
    in.patientName = patient;
    in.patientId = id;
    in.studyInstanceUid = study;
    in.studyDate = date;
    in.seriesInstanceUid = series;
    in.modality = modality;
    in.sopInstanceUid = sop;
    in.transferSyntaxUid = "1.2.840.10008.1.2.1";
    return in;
}

std::vector<dicom::DicomInstance> sample(const test::TempDir& dir) {
    std::vector<dicom::DicomInstance> v;
    for (int i = 0; i < 3; ++i) {
        const std::string f = dir.file("a" + std::to_string(i));
        std::ofstream(f) << "x";
        v.push_back(instance(f, "DOE^JANE", "P1", "1.1", "20240105", "1.1.1", "CT", "1.1.1." + std::to_string(i)));
    }
    std::ofstream(dir.file("b0")) << "x";
    v.push_back(instance(dir.file("b0"), "DOE^JANE", "P1", "1.1", "20240105", "1.1.2", "MR", "1.1.2.0"));
    std::ofstream(dir.file("c0")) << "x";
    v.push_back(instance(dir.file("c0"), "ROE^RICHARD", "P2", "2.1", "20231120", "2.1.1", "MR", "2.1.1.0"));
    return v;
}
}  // namespace

TEST(StudyDatabase, ReimportIsIdempotent) {
    test::TempDir dir;
    dicom::StudyDatabase db(dir.file("db/studies.sqlite"));
    const auto in = sample(dir);
    auto s = db.addInstances(in);
    EXPECT_EQ(s.added, 5u);
    s = db.addInstances(in);
    EXPECT_EQ(s.added, 0u);
    EXPECT_EQ(s.unchanged, 5u);
    EXPECT_EQ(db.instanceCount(), 5u);
    const auto studies = db.findStudies({});
    ASSERT_EQ(studies.size(), 2u);
    EXPECT_EQ(studies[0].patientName, "DOE^JANE");  // newest first
    EXPECT_EQ(studies[0].modalities, "CT\\MR");
    EXPECT_EQ(studies[0].seriesCount, 2);
    const auto series = db.seriesOfStudy("1.1");
    ASSERT_EQ(series.size(), 2u);
    EXPECT_EQ(series[0].instanceCount + series[1].instanceCount, 4);
}

TEST(StudyDatabase, QueriesByNameIdDateRangeAndModality) {
    test::TempDir dir;
    dicom::StudyDatabase db(dir.file("s.sqlite"));
    db.addInstances(sample(dir));
    auto q = [&](dicom::StudyQuery query) { return db.findStudies(query).size(); };
    EXPECT_EQ(q({"roe", "", "", ""}), 1u);
    EXPECT_EQ(q({"DOE*", "", "", ""}), 1u);
    EXPECT_EQ(q({"*E^*", "", "", ""}), 2u);
    EXPECT_EQ(q({"P2", "", "", ""}), 1u);
    EXPECT_EQ(q({"", "20240101", "", ""}), 1u);
    EXPECT_EQ(q({"", "", "20231231", ""}), 1u);
    EXPECT_EQ(q({"", "20231101", "20240201", ""}), 2u);
    EXPECT_EQ(q({"", "", "", "CT"}), 1u);
    EXPECT_EQ(q({"", "", "", "MR"}), 2u);
    EXPECT_EQ(q({"nobody", "", "", ""}), 0u);
}

TEST(StudyDatabase, DeletedFilesArePrunedOnlyWhenAsked) {
    test::TempDir dir;
    dicom::StudyDatabase db(dir.file("s.sqlite"));
    db.addInstances(sample(dir));
    std::filesystem::remove(dir.file("c0"));
    std::filesystem::remove(dir.file("a1"));
    const auto check = db.checkFiles();  // what `studies` and the browser run: marks, never deletes
    EXPECT_EQ(check.offline, 2u);
    EXPECT_EQ(db.offlineCount(), 2u);
    EXPECT_EQ(db.instanceCount(), 5u);
    EXPECT_EQ(db.findStudies({}).size(), 2u);
    const auto pruned = db.prune();  // the files are gone from a folder that is still there
    EXPECT_EQ(pruned.removed, 2u);
    EXPECT_EQ(pruned.kept, 0u);
    EXPECT_EQ(db.findStudies({}).size(), 1u);
    EXPECT_EQ(db.filesOfSeries("1.1.1").size(), 2u);
    dicom::SeriesRow row;
    EXPECT_FALSE(db.findSeries("2.1.1", row));
    ASSERT_TRUE(db.findSeries("1.1.1", row));
    EXPECT_EQ(row.instanceCount, 2);
}

// The storage folder unmounted or renamed: every row stays, marked offline, and comes back
// online with the folder; even prune keeps rows whose folder is missing.
TEST(StudyDatabase, UnreachableFolderLosesNothing) {
    test::TempDir dir;
    const auto store = dir.path() / "store" / "study";
    std::filesystem::create_directories(store);
    std::vector<dicom::DicomInstance> in;
    for (int i = 0; i < 4; ++i) {
        const std::string f = (store / ("i" + std::to_string(i))).string();
        std::ofstream(f) << "x";
        in.push_back(instance(f, "DOE^JANE", "P1", "1.1", "20240105", "1.1.1", "CT", "1.1.1." + std::to_string(i)));
    }
    dicom::StudyDatabase db(dir.file("s.sqlite"));
    db.addInstances(in);
    db.setSeriesOctree("1.1.1", "/somewhere/x.hvo");
    std::filesystem::rename(dir.path() / "store", dir.path() / "elsewhere");
    EXPECT_EQ(db.checkFiles().offline, 4u);
    const auto pruned = db.prune();
    EXPECT_EQ(pruned.removed, 0u);
    EXPECT_EQ(pruned.kept, 4u);
    EXPECT_EQ(db.instanceCount(), 4u);
    dicom::SeriesRow row;
    ASSERT_TRUE(db.findSeries("1.1.1", row));
    EXPECT_EQ(row.octreePath, "/somewhere/x.hvo");
    std::filesystem::rename(dir.path() / "elsewhere", dir.path() / "store");
    const auto back = db.checkFiles();
    EXPECT_EQ(back.offline, 0u);
    EXPECT_EQ(back.backOnline, 4u);
    EXPECT_EQ(db.offlineCount(), 0u);
}

// A real unmount (a bind mount taken away): the files sat at the mount point's top, whose
// folder stays behind, empty. Nothing is deleted, even by prune; all is back when it returns.
TEST(StudyDatabase, UnmountedDiskLeavesAnEmptyMountPointAndLosesNothing) {
    test::TempDir dir;
    const auto disk = dir.path() / "disk";
    const auto mnt = dir.path() / "mnt";
    std::filesystem::create_directories(disk);
    std::filesystem::create_directories(mnt);
    std::vector<dicom::DicomInstance> in;
    for (int i = 0; i < 3; ++i) {
        std::ofstream((disk / ("i" + std::to_string(i))).string()) << "x";
        in.push_back(instance((mnt / ("i" + std::to_string(i))).string(), "DOE^JANE", "P1", "1.1", "20240105", "1.1.1",
                              "CT", "1.1.1." + std::to_string(i)));
    }
    const std::string bind = "mount --bind " + disk.string() + " " + mnt.string() + " 2>&1";
    if (std::system(bind.c_str()) != 0) GTEST_SKIP() << "cannot bind-mount here (needs root)";
    struct Unmount {  // whatever fails below, the mount does not outlive the test
        std::string at;
        ~Unmount() { (void)std::system(("umount " + at + " 2>/dev/null").c_str()); }
    } unmount{mnt.string()};
    dicom::StudyDatabase db(dir.file("s.sqlite"));
    db.addInstances(in);
    EXPECT_EQ(db.checkFiles().offline, 0u);
    ASSERT_EQ(std::system(("umount " + mnt.string()).c_str()), 0);
    EXPECT_EQ(db.checkFiles().offline, 3u);
    const auto pruned = db.prune();
    EXPECT_EQ(pruned.removed, 0u) << "an empty mount point is an unmounted disk, not deleted files";
    EXPECT_EQ(pruned.kept, 3u);
    EXPECT_EQ(db.instanceCount(), 3u);
    ASSERT_EQ(std::system(bind.c_str()), 0);
    EXPECT_EQ(db.checkFiles().backOnline, 3u);
}

// A database written before the offline flag (schema 1) is migrated, and one from a newer
// Holovox is refused with a sentence.
TEST(StudyDatabase, SchemaIsMigratedAndNewerRefused) {
    test::TempDir dir;
    const std::string path = dir.file("old.sqlite");
    ASSERT_EQ(std::system(("sqlite3 " + path +
                           " \"CREATE TABLE instances (id INTEGER PRIMARY KEY, sop_uid TEXT NOT NULL UNIQUE, series INTEGER "
                           "NOT NULL, path TEXT NOT NULL, transfer_syntax TEXT, sop_class TEXT, instance_number INTEGER, "
                           "file_size INTEGER); CREATE TABLE series (id INTEGER PRIMARY KEY, uid TEXT NOT NULL UNIQUE, "
                           "study INTEGER NOT NULL, number INTEGER, description TEXT, modality TEXT, body_part TEXT, "
                           "instance_count INTEGER NOT NULL DEFAULT 0, octree TEXT);\"").c_str()),
              0);
    {
        dicom::StudyDatabase db(path);
        EXPECT_EQ(db.checkFiles().offline, 0u);
        db.addInstances(sample(dir));
        EXPECT_EQ(db.instanceCount(), 5u);
        db.setSeriesWarnings("1.1.1", {"PixelSpacing is missing", "1 missing slice(s)"});  // a column version 4 added
        dicom::SeriesRow row;
        ASSERT_TRUE(db.findSeries("1.1.1", row));
        EXPECT_EQ(row.warnings, (std::vector<std::string>{"PixelSpacing is missing", "1 missing slice(s)"}));
    }
    ASSERT_EQ(std::system(("sqlite3 " + path + " 'PRAGMA user_version = 9;'").c_str()), 0);
    try {
        dicom::StudyDatabase db(path);
        FAIL() << "a newer schema was opened";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("newer Holovox"), std::string::npos) << e.what();
    }
}

TEST(StudyDatabase, OctreePathIsRecordedAndCorruptFileRefused) {
    test::TempDir dir;
    {
        dicom::StudyDatabase db(dir.file("s.sqlite"));
        db.addInstances(sample(dir));
        db.setSeriesOctree("1.1.1", "/tmp/x.hvo");
    }
    dicom::StudyDatabase again(dir.file("s.sqlite"));
    dicom::SeriesRow row;
    ASSERT_TRUE(again.findSeries("1.1.1", row));
    EXPECT_EQ(row.octreePath, "/tmp/x.hvo");
    std::ofstream(dir.file("junk.sqlite")) << std::string(5000, 'j');
    EXPECT_THROW(dicom::StudyDatabase(dir.file("junk.sqlite")), core::Error);
}

// UID collisions, as a faulty anonymiser makes them: images naming a study of another patient,
// a series of another study or a SOP Instance UID of another series are refused and named,
// never filed there; two different images of one SOP Instance UID keep the first. Within one
// batch and across imports alike. What was filed stays as it was.
TEST(StudyDatabase, UidCollisionsAreRefusedNeverFiledUnderAnotherPatient) {
    test::TempDir dir;
    dicom::StudyDatabase db(dir.file("s.sqlite"));
    const auto file = [&](const std::string& name) {
        std::ofstream(dir.file(name)) << "x";
        return dir.file(name);
    };
    std::vector<dicom::DicomInstance> batch = {
        instance(file("ann1"), "ALPHA^ANN", "A1", "9.1", "20240101", "9.1.1", "CT", "9.1.1.1"),
        // Bob's image in Ann's series (another study): refused.
        instance(file("bob1"), "BETA^BOB", "B1", "9.2", "20240101", "9.1.1", "CT", "9.2.1.1"),
        // Bob's image in Ann's study: refused.
        instance(file("bob2"), "BETA^BOB", "B1", "9.1", "20240101", "9.1.2", "CT", "9.1.2.1"),
    };
    auto s = db.addInstances(batch);
    EXPECT_EQ(s.added, 1u);
    EXPECT_EQ(s.refused, (std::vector<std::size_t>{1, 2}));
    ASSERT_EQ(s.conflicts.size(), 2u);
    EXPECT_NE(s.conflicts[0].find("series 9.1.1 is filed under study 9.1, not study 9.2 of BETA^BOB (B1)"), std::string::npos)
        << s.conflicts[0];
    EXPECT_NE(s.conflicts[1].find("study 9.1 is filed under patient ALPHA^ANN (A1), not BETA^BOB (B1)"), std::string::npos)
        << s.conflicts[1];
    EXPECT_EQ(s.accepted(batch).size(), 1u);
    // Ann's name as another system writes it (case, empty trailing components) is still Ann;
    // a name stored as Latin-1 bytes is the same name converted to UTF-8.
    s = db.addInstances({instance(file("ann2"), "Alpha^Ann^^", "A1", "9.1", "20240101", "9.1.1", "CT", "9.1.1.2")});
    EXPECT_TRUE(s.conflicts.empty()) << s.conflicts.front();
    db.addInstances({instance(file("m1"), "M\xdcLLER^HANS", "M1", "9.5", "20240101", "9.5.1", "CT", "9.5.1.1")});
    s = db.addInstances({instance(file("m2"), "M\u00dcLLER^HANS^", "M1", "9.5", "20240101", "9.5.1", "CT", "9.5.1.2")});
    EXPECT_TRUE(s.conflicts.empty()) << s.conflicts.front();
    EXPECT_EQ(s.added, 1u);
    dicom::StudyQuery bob;
    bob.text = "BETA";
    EXPECT_TRUE(db.findStudies(bob).empty()) << "Bob has no study filed";
    // Across imports: Ann's SOP Instance UID in Bob's own series is refused, not moved there.
    s = db.addInstances({instance(file("bob3"), "BETA^BOB", "B1", "9.3", "20240101", "9.3.1", "CT", "9.1.1.1")});
    EXPECT_EQ(s.refused.size(), 1u);
    ASSERT_EQ(s.conflicts.size(), 1u);
    EXPECT_NE(s.conflicts[0].find("filed in series 9.1.1, not series 9.3.1"), std::string::npos) << s.conflicts[0];
    EXPECT_EQ(db.filesOfSeries("9.1.1"), (std::vector<std::string>{dir.file("ann1"), dir.file("ann2")}));
    // Two different images (other instance numbers) of one SOP Instance UID in one batch.
    auto a = instance(file("c1"), "ALPHA^ANN", "A1", "9.1", "20240101", "9.1.1", "CT", "9.1.1.7");
    auto b = instance(file("c2"), "ALPHA^ANN", "A1", "9.1", "20240101", "9.1.1", "CT", "9.1.1.7");
    a.instanceNumber = 7;
    b.instanceNumber = 8;
    s = db.addInstances({a, b});
    EXPECT_EQ(s.added, 1u);
    EXPECT_EQ(s.refused, (std::vector<std::size_t>{1}));
    ASSERT_EQ(s.conflicts.size(), 1u);
    EXPECT_NE(s.conflicts[0].find("share their SOP Instance UID with another image"), std::string::npos) << s.conflicts[0];
}

// A series that gains images after its octree was built forgets the octree (it had opened the
// stale one, interpolated across the slices that came since); paths are stored absolute.
TEST(StudyDatabase, ASeriesThatGainsImagesForgetsItsOctree) {
    test::TempDir dir;
    dicom::StudyDatabase db(dir.file("s.sqlite"));
    auto in = sample(dir);
    db.addInstances({in[0], in[1]});
    db.setSeriesOctree("1.1.1", dir.file("x.hvo"));
    db.addInstances({in[0], in[1]});  // nothing new: kept
    dicom::SeriesRow row;
    ASSERT_TRUE(db.findSeries("1.1.1", row));
    EXPECT_EQ(row.octreePath, dir.file("x.hvo"));
    db.addInstances({in[2]});
    ASSERT_TRUE(db.findSeries("1.1.1", row));
    EXPECT_EQ(row.octreePath, "");
    EXPECT_EQ(row.instanceCount, 3);
    for (const auto& f : db.filesOfSeries("1.1.1")) EXPECT_TRUE(std::filesystem::path(f).is_absolute()) << f;
}

// Removing a study deletes only what Holovox received, where it receives it (storage/<study>/
// <series>/<sop>.dcm, a plain file) and octrees named for the study's own series: a file of the
// user's inside the storage folder, a link of the user's to a received file, every file under a
// storage folder of "/", an octree of a series whose UID merely begins the same way, and one the
// database records for another series all stay.
TEST(StudyDatabase, RemovingAStudyDeletesOnlyWhatWasReceivedWhereItIsReceived) {
    namespace fs = std::filesystem;
    test::TempDir dir;
    const std::string storage = dir.file("storage"), octrees = dir.file("db/octrees");
    fs::create_directories(storage + "/1.9/1.9.1");
    fs::create_directories(storage + "/mine");
    fs::create_directories(dir.file("user"));
    fs::create_directories(octrees);
    auto touch = [](const std::string& path) {
        std::ofstream(path) << "x";
        return path;
    };
    dicom::StudyDatabase db(dir.file("db/s.sqlite"));
    const std::string received = touch(storage + "/1.9/1.9.1/1.9.1.1.dcm"), target = touch(storage + "/1.9/1.9.1/1.9.1.3.dcm");
    const std::string inStorage = touch(storage + "/mine/1.9.1.2.dcm"), own = touch(dir.file("user/own.dcm"));
    fs::create_symlink(target, dir.file("user/link.dcm"));
    auto s = db.addInstances({instance(received, "A^A", "A", "1.9", "20240101", "1.9.1", "CT", "1.9.1.1"),
                              instance(inStorage, "A^A", "A", "1.9", "20240101", "1.9.1", "CT", "1.9.1.2"),
                              instance(target, "A^A", "A", "1.9", "20240101", "1.9.1", "CT", "1.9.1.3"),
                              instance(dir.file("user/link.dcm"), "A^A", "A", "1.9", "20240101", "1.9.1", "CT", "1.9.1.4"),
                              instance(own, "A^A", "A", "1.9", "20240101", "1.9.1", "CT", "1.9.1.5"),
                              instance(touch(dir.file("user/b.dcm")), "B^B", "B", "1.8", "20240101", "1.9.1-v2", "CT", "1.8.1.1"),
                              instance(touch(dir.file("user/c.dcm")), "C^C", "C", "1.7", "20240101", "1.7.1", "CT", "1.7.1.1")});
    ASSERT_EQ(s.added, 7u);
    for (const char* name : {"1.9.1.hvo", "1.9.1.preview.hvo", "1.9.1-v2.preview.hvo", "1.9.1-stack2.hvo", "1.9.1-v2.hvo",
                             "1.9.10.hvo", "1.9.1.hvo.bak"})
        touch(octrees + "/" + name);
    db.setSeriesOctree("1.9.1-v2", octrees + "/1.9.1-v2.hvo");  // another study's series records it

    const auto r = dicom::StudyRemoval::remove(db, "1.9", storage, octrees);
    EXPECT_EQ(r.patient, "A^A (A)");
    EXPECT_EQ(r.forgotten, 5u);
    EXPECT_EQ(r.deleted, 2u);  // the received file and the link's target, both where received
    EXPECT_EQ(r.kept, 3u);
    EXPECT_TRUE(r.failed.empty());
    EXPECT_FALSE(fs::exists(received));
    EXPECT_FALSE(fs::exists(storage + "/1.9"));  // the emptied series and study folders
    EXPECT_TRUE(fs::exists(inStorage));
    EXPECT_TRUE(fs::exists(own));
    EXPECT_TRUE(fs::is_symlink(dir.file("user/link.dcm")));
    EXPECT_EQ(r.octrees, 4u);
    for (const char* gone : {"1.9.1.hvo", "1.9.1.preview.hvo", "1.9.1-v2.preview.hvo", "1.9.1-stack2.hvo"})
        EXPECT_FALSE(fs::exists(octrees + "/" + gone)) << gone;
    for (const char* kept : {"1.9.1-v2.hvo", "1.9.10.hvo", "1.9.1.hvo.bak"}) EXPECT_TRUE(fs::exists(octrees + "/" + kept)) << kept;

    // A storage folder of "/" makes no file of the user's a received one.
    const auto c = dicom::StudyRemoval::remove(db, "1.7", "/", octrees);
    EXPECT_EQ(c.deleted, 0u);
    EXPECT_EQ(c.kept, 1u);
    EXPECT_TRUE(fs::exists(dir.file("user/c.dcm")));
    EXPECT_THROW(dicom::StudyRemoval::remove(db, "1.9", storage, octrees), core::Error);
}

// A study removed while one of its series' octrees is being built (a retrieve's build, the
// GUI's open-series job, the CLI's import --build): the finished octree is recorded nowhere, so
// it is deleted, with its label names beside it, and the build says why instead of leaving it.
TEST(StudyDatabase, AnOctreeFinishedAfterItsStudyWasRemovedIsDeletedNotLeftBehind) {
    namespace fs = std::filesystem;
    test::TempDir dir;
    dicom::StudyDatabase db(dir.file("s.sqlite"));
    db.addInstances(sample(dir));
    auto touch = [](const std::string& path) {
        std::ofstream(path) << "x";
        return path;
    };
    const std::string kept = touch(dir.file("kept.hvo"));
    dicom::SeriesOctree::record(db, "1.1.1", kept);
    dicom::SeriesRow row;
    ASSERT_TRUE(db.findSeries("1.1.1", row));
    EXPECT_EQ(row.octreePath, kept);
    db.removeStudy("1.1");
    const std::string late = touch(dir.file("late.hvo")), names = touch(dir.file("late.hvo.ctbl"));
    try {
        dicom::SeriesOctree::record(db, "1.1.1", late);
        ADD_FAILURE() << "recorded an octree for a removed series";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("removed while its octree was built"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(late));
    EXPECT_FALSE(fs::exists(names));
    const std::string volume = touch(dir.file("late-v2.hvo"));
    EXPECT_THROW(dicom::SeriesOctree::record(db, "1.1.1", volume, 2), core::Error);
    EXPECT_FALSE(fs::exists(volume));
    EXPECT_FALSE(db.setSeriesOctree("9.9.9", dir.file("none.hvo")));
    EXPECT_TRUE(db.setSeriesOctree("2.1.1", dir.file("other.hvo"))) << "another study's series is still there";
}

// Two study databases sharing one storage folder (the PACS settings name one folder; --db picks
// another database): removing a study from one keeps the received files the other still
// indexes, and says so; once neither does, they go. A listed database that cannot be read keeps
// every file.
TEST(StudyDatabase, RemovingAStudyKeepsReceivedFilesAnotherDatabaseSharingTheFolderIndexes) {
    namespace fs = std::filesystem;
    test::TempDir dir;
    const std::string storage = dir.file("storage");
    fs::create_directories(storage + "/1.9/1.9.1");
    const std::string received = storage + "/1.9/1.9.1/1.9.1.1.dcm";
    std::ofstream(received) << "x";
    const auto in = instance(received, "A^A", "A", "1.9", "20240101", "1.9.1", "CT", "1.9.1.1");
    dicom::StudyDatabase a(dir.file("a/s.sqlite")), b(dir.file("b/s.sqlite"));
    a.addInstances({in});
    b.addInstances({in});
    for (int twice = 0; twice < 2; ++twice) {
        dicom::StorageOwners::add(storage, a.path());
        dicom::StorageOwners::add(storage, b.path());
    }
    std::ifstream list(storage + "/" + dicom::StorageOwners::kListName);
    std::size_t lines = 0;
    for (std::string line; std::getline(list, line);) ++lines;
    EXPECT_EQ(lines, 2u) << "each database listed once";
    const auto fromA = dicom::StudyRemoval::remove(a, "1.9", storage, dir.file("a/octrees"));
    EXPECT_EQ(fromA.forgotten, 1u);
    EXPECT_EQ(fromA.deleted, 0u);
    EXPECT_EQ(fromA.shared, 1u);
    ASSERT_EQ(fromA.sharers.size(), 1u);
    EXPECT_EQ(fs::path(fromA.sharers[0]).filename(), "s.sqlite");
    EXPECT_TRUE(fs::exists(received)) << "the other database still indexes it";
    EXPECT_EQ(b.instanceCount(), 1u);
    const auto fromB = dicom::StudyRemoval::remove(b, "1.9", storage, dir.file("b/octrees"));
    EXPECT_EQ(fromB.deleted, 1u);
    EXPECT_EQ(fromB.shared, 0u);
    EXPECT_FALSE(fs::exists(received));

    // A third database listed that is not a database at all: nothing is deleted, and why is said.
    fs::create_directories(storage + "/1.9/1.9.1");
    std::ofstream(received) << "x";
    a.addInstances({in});
    std::ofstream(dir.file("c.sqlite")) << "not a database";
    dicom::StorageOwners::add(storage, dir.file("c.sqlite"));
    const auto unread = dicom::StudyRemoval::remove(a, "1.9", storage, dir.file("a/octrees"));
    EXPECT_EQ(unread.deleted, 0u);
    EXPECT_EQ(unread.shared, 1u);
    ASSERT_EQ(unread.sharers.size(), 1u);
    EXPECT_NE(unread.sharers[0].find("cannot read that study database"), std::string::npos) << unread.sharers[0];
    EXPECT_TRUE(fs::exists(received));
}
