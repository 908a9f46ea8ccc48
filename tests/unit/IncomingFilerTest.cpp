// The filer that stores a WADO-RS transfer's instances while the next ones arrive: every
// instance is filed byte for byte and reported once, in the order it arrived, on the receiving
// thread; more than the pending limit at once wait rather than pile up; a part that is not
// DICOM is removed and reported at the end without losing the others; a slow transfer is reported
// instance by instance.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "core/base/Error.h"
#include "core/base/JobContext.h"
#include "core/volume/PhantomVoxelSource.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomSeriesWriter.h"
#include "dicom/IncomingFiler.h"
#include "dicom/IncomingStore.h"
#include "dicom/UidPath.h"
#include "tests/support/TempDir.h"

using namespace hvx;
namespace fs = std::filesystem;

namespace {
std::string bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// What a receiver does with one part: the bytes into a fresh temporary file of the store.
std::string receive(dicom::IncomingStore& store, const std::string& bytes) {
    int fd = -1;
    const std::string tmp = store.temporaryFile(fd);
    EXPECT_EQ(::write(fd, bytes.data(), bytes.size()), ssize_t(bytes.size()));
    ::close(fd);
    return tmp;
}

/// A phantom series of `slices` instances written as DICOM files under `dir`.
std::vector<std::string> phantomSeries(test::TempDir& dir, std::uint32_t slices, std::uint64_t seed) {
    core::PhantomVoxelSource phantom({16, 16, slices}, seed);
    core::JobContext job;
    return dicom::DicomSeriesWriter::write(phantom, dir.file("s"), {}, job);
}
}  // namespace

TEST(IncomingFiler, FilesEveryInstanceInOrderAndReportsABadPartAtTheEnd) {
    test::TempDir src, dir;
    const auto files = phantomSeries(src, 150, 5);
    ASSERT_EQ(files.size(), 150u);  // more than IncomingFiler::kMaxPending: submit() must wait
    dicom::IncomingStore store(dir.file("rx"));
    std::vector<std::string> sent, reported;
    const auto receiving = std::this_thread::get_id();
    bool otherThread = false;
    const auto onStored = [&](const dicom::DicomInstance& in) {
        otherThread |= std::this_thread::get_id() != receiving;
        reported.push_back(in.sopInstanceUid);
        EXPECT_EQ(in.path.rfind(dir.file("rx") + "/", 0), 0u) << in.path;
    };
    {
        dicom::IncomingFiler filer(store);
        for (std::size_t i = 0; i < files.size(); ++i) {
            dicom::DicomInstance in;
            ASSERT_EQ(dicom::DicomHeaderReader::read(files[i], in), dicom::DicomHeaderReader::Kind::Dicom);
            sent.push_back(in.sopInstanceUid);
            filer.submit(receive(store, bytesOf(files[i])), onStored);
            if (i == 70) filer.submit(receive(store, "this part is not a DICOM instance"), onStored);
        }
        try {
            filer.finish(onStored);
            ADD_FAILURE() << "the part that is not DICOM was not reported";
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find("not DICOM"), std::string::npos) << e.what();
        }
    }
    EXPECT_FALSE(otherThread) << "onStored ran on a filer thread";
    EXPECT_EQ(reported, sent) << "every instance once, in the order it arrived";
    std::size_t stored = 0;
    for (const auto& f : fs::recursive_directory_iterator(dir.file("rx"))) stored += f.is_regular_file();
    EXPECT_EQ(stored, files.size()) << "nothing left in .incoming, nothing but the instances filed";
    for (std::size_t i = 0; i < files.size(); i += 37) {
        dicom::DicomInstance in;
        dicom::DicomHeaderReader::read(files[i], in);
        const auto path = fs::path(dir.file("rx")) / dicom::UidPath::component(in.studyInstanceUid) /
                          dicom::UidPath::component(in.seriesInstanceUid) /
                          (dicom::UidPath::component(in.sopInstanceUid) + ".dcm");
        EXPECT_EQ(bytesOf(path.string()), bytesOf(files[i])) << "filed byte for byte: " << path;
    }
}

// A filer destroyed in the middle of a transfer (the transfer failed) waits for the files it
// took: nothing is left half-moved in .incoming.
TEST(IncomingFiler, DestroyedMidTransferLeavesNothingHalfDone) {
    test::TempDir src, dir;
    const auto files = phantomSeries(src, 40, 6);
    dicom::IncomingStore store(dir.file("rx"));
    {
        dicom::IncomingFiler filer(store);
        for (const auto& f : files) filer.submit(receive(store, bytesOf(f)), {});
    }
    EXPECT_TRUE(fs::is_empty(fs::path(dir.file("rx")) / ".incoming"));
}

// Renames wait for one folder flush in rounds (IncomingFiler::kFlushRound) only while files
// keep coming: in a slow transfer each instance is still reported as the next one arrives, so
// the progress never lags a round behind.
TEST(IncomingFiler, ASlowTransferIsReportedInstanceByInstance) {
    test::TempDir src, dir;
    const auto files = phantomSeries(src, 3, 7);
    dicom::IncomingStore store(dir.file("rx"));
    std::size_t reported = 0;
    const auto onStored = [&](const dicom::DicomInstance&) { ++reported; };
    dicom::IncomingFiler filer(store);
    for (std::size_t i = 0; i < files.size(); ++i) {
        filer.submit(receive(store, bytesOf(files[i])), onStored);
        EXPECT_EQ(reported, i) << "reported when instance " << i + 1 << " arrived";
        std::this_thread::sleep_for(dicom::IncomingFiler::kFlushDelay * 50);  // the network is slow
    }
    filer.finish(onStored);
    EXPECT_EQ(reported, files.size());
}
