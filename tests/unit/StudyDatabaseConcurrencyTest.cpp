// Two imports and a retrieve write into one study database at once, each through its own
// connection, as the GUI's jobs and the storage receiver do. Nothing may be lost, nothing may
// land under another patient, and no writer may fail on a busy database.
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <atomic>
#include <set>
#include <fstream>
#include <mutex>
#include <thread>

#include "dicom/SeriesOctree.h"
#include "dicom/StudyDatabase.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
constexpr int kInstances = 120;

struct Writer {
    std::string patient;  ///< patient ID; also the study and series UID roots
    int batch;            ///< instances per addInstances call (1: the receiver, one per C-STORE)
    bool recordsOctrees;  ///< like a retrieve: records an octree and reads the browser's lists
};

dicom::DicomInstance instanceOf(const test::TempDir& dir, const Writer& w, int i) {
    dicom::DicomInstance in;
    in.path = dir.file(w.patient + "_" + std::to_string(i) + ".dcm");
    std::ofstream(in.path) << w.patient;
    in.patientName = "PATIENT^" + w.patient;
    in.patientId = w.patient;
    in.studyInstanceUid = "1.2." + w.patient.substr(1);
    in.studyDate = "20240105";
    in.seriesInstanceUid = in.studyInstanceUid + ".1";
    in.modality = "CT";
    in.sopInstanceUid = in.seriesInstanceUid + "." + std::to_string(i + 1);
    in.instanceNumber = i + 1;
    in.transferSyntaxUid = "1.2.840.10008.1.2.1";
    return in;
}

void write(const test::TempDir& dir, const std::string& dbPath, const Writer& w, const std::atomic<bool>& go) {
    while (!go.load()) std::this_thread::yield();
    dicom::StudyDatabase db(dbPath);  // every writer opens (and may create) the file at once
    std::vector<dicom::DicomInstance> pending;
    for (int i = 0; i < kInstances; ++i) {
        pending.push_back(instanceOf(dir, w, i));
        if (static_cast<int>(pending.size()) < w.batch && i + 1 < kInstances) continue;
        db.addInstances(pending);
        pending.clear();
        if (w.recordsOctrees && i % 10 == 9) {
            db.setSeriesOctree(instanceOf(dir, w, 0).seriesInstanceUid, dir.file(w.patient + ".hvo"));
            (void)db.findStudies({});
        }
    }
}
}  // namespace

TEST(StudyDatabaseConcurrency, TwoImportsAndARetrieveAtOnceLoseNothingAndMixNoPatients) {
    test::TempDir dir;
    const std::string dbPath = dir.file("db/studies.sqlite");
    const std::vector<Writer> writers = {{"P1", 7, false}, {"P2", 13, false}, {"P3", 1, true}};
    std::atomic<bool> go{false};
    std::mutex failuresLock;
    std::vector<std::string> failures;
    std::vector<std::thread> threads;
    for (const Writer& w : writers) {
        threads.emplace_back([&, w] {
            try {
                write(dir, dbPath, w, go);
            } catch (const std::exception& e) {
                std::lock_guard<std::mutex> lock(failuresLock);
                failures.push_back(w.patient + ": " + e.what());
            }
        });
    }
    go = true;
    for (auto& t : threads) t.join();
    for (const auto& f : failures) ADD_FAILURE() << f;

    dicom::StudyDatabase db(dbPath);
    EXPECT_EQ(db.instanceCount(), writers.size() * kInstances);
    const auto studies = db.findStudies({});
    ASSERT_EQ(studies.size(), writers.size());
    for (const Writer& w : writers) {
        const auto first = instanceOf(dir, w, 0);
        const auto series = db.seriesOfStudy(first.studyInstanceUid);
        ASSERT_EQ(series.size(), 1u) << w.patient;
        EXPECT_EQ(series[0].instanceCount, kInstances) << w.patient;
        const auto files = db.filesOfSeries(first.seriesInstanceUid);
        ASSERT_EQ(files.size(), static_cast<std::size_t>(kInstances)) << w.patient;
        for (int i = 0; i < kInstances; ++i) EXPECT_EQ(files[i], instanceOf(dir, w, i).path) << w.patient;
        EXPECT_EQ(series[0].octreePath, w.recordsOctrees ? dir.file(w.patient + ".hvo") : "") << w.patient;
    }
    for (const auto& s : studies) EXPECT_EQ(s.patientName, "PATIENT^" + s.patientId);
}

// Creating the file, switching it to WAL and creating the schema from several connections at
// once made SQLite refuse one of them without waiting ("database is locked"), one run in five.
TEST(StudyDatabaseConcurrency, EightJobsOpeningANewDatabaseAtOnceAllSucceed) {
    for (int round = 0; round < 20; ++round) {
        test::TempDir dir;
        const std::string dbPath = dir.file("db/studies.sqlite");
        std::atomic<bool> go{false};
        std::atomic<int> opened{0};
        std::mutex failuresLock;
        std::vector<std::string> failures;
        std::vector<std::thread> threads;
        for (int t = 0; t < 8; ++t) {
            threads.emplace_back([&] {
                while (!go.load()) std::this_thread::yield();
                try {
                    dicom::StudyDatabase db(dbPath);
                    (void)db.instanceCount();
                    ++opened;
                } catch (const std::exception& e) {
                    std::lock_guard<std::mutex> lock(failuresLock);
                    failures.push_back(e.what());
                }
            });
        }
        go = true;
        for (auto& t : threads) t.join();
        for (const auto& f : failures) ADD_FAILURE() << "round " << round << ": " << f;
        ASSERT_EQ(opened.load(), 8) << "round " << round;
    }
}

// A retrieve's receiver files every instance under the retrieve's lock. A series that grew (a
// second retrieve of it) is read again from all its files; that reading must not hold the lock,
// or the receiver stalls behind it. The files' opens are watched with inotify: the lock must be
// free while some of the series' files are still unread.
TEST(StudyDatabaseConcurrency, AGrownSeriesIsReadAgainWithoutHoldingTheRetrievesLock) {
    test::TempDir dir;
    dicom::StudyDatabase db(dir.file("db/studies.sqlite"));
    const Writer w{"P7", 1, false};
    constexpr int kFiles = 1000;
    std::vector<dicom::DicomInstance> all;
    for (int i = 0; i < kFiles; ++i) {
        all.push_back(instanceOf(dir, w, i));
        std::ofstream(all.back().path) << "not a DICOM file, only bytes to read " << i;
    }
    ASSERT_EQ(db.addInstances(all).added, std::size_t(kFiles));
    dicom::SeriesVolume scanned;  // what the last retrieve brought: one image of the series
    scanned.seriesUid = all.front().seriesInstanceUid;
    const std::vector<dicom::DicomInstance> batch{all.front()};

    const int watch = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    ASSERT_GE(watch, 0);
    ASSERT_GE(::inotify_add_watch(watch, dir.path().c_str(), IN_OPEN), 0);
    std::mutex retrieveLock;
    std::atomic<bool> finished{false};
    std::thread record([&] {
        dicom::SeriesOctree::recordVolumes(db, {scanned}, batch, &retrieveLock);
        finished = true;
    });
    std::set<std::string> opened;
    auto drain = [&] {
        alignas(inotify_event) char buffer[1 << 16];
        for (ssize_t n; (n = ::read(watch, buffer, sizeof buffer)) > 0;)
            for (char* at = buffer; at < buffer + n;) {
                const auto* e = reinterpret_cast<const inotify_event*>(at);
                if (e->len > 0 && std::string(e->name).find(".dcm") != std::string::npos) opened.insert(e->name);
                at += sizeof(inotify_event) + e->len;
            }
    };
    while (opened.empty() && !finished) {  // the reading has begun
        pollfd p{watch, POLLIN, 0};
        ::poll(&p, 1, 100);
        drain();
    }
    bool lockedWhileReading = false;
    while (!finished) {
        if (retrieveLock.try_lock()) {
            drain();  // every open before this moment is queued
            lockedWhileReading = opened.size() < std::size_t(kFiles);
            retrieveLock.unlock();
            break;
        }
        std::this_thread::yield();
    }
    record.join();
    drain();
    ::close(watch);
    EXPECT_TRUE(lockedWhileReading) << "the lock was free only once " << opened.size() << " of " << kFiles
                                    << " files had been opened";
    EXPECT_EQ(opened.size(), std::size_t(kFiles)) << "every file of the grown series is read again";
}
