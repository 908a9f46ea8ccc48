// Where received instances land: unique temporary names across stores (two retrieves at once),
// the same instance twice is a no-op, another object under the same SOP Instance UID is set
// aside and never replaces the stored one, and sanitised UIDs cannot collide. And the atomic
// writer used for every other output: two writers of one target never share a temporary file.
// Importing a storage folder reads its instances, not what receives keep beside them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>

#include "core/base/AtomicFileWriter.h"
#include "core/base/Error.h"
#include "core/base/JobContext.h"
#include "dicom/DicomScanner.h"
#include "dicom/IncomingStore.h"
#include "dicom/StorageOwners.h"
#include "dicom/UidPath.h"
#include "tests/support/TempDir.h"

using namespace hvx;
namespace fs = std::filesystem;

namespace {
const std::string ctSmall = "/usr/lib/python3/dist-packages/pydicom/data/test_files/CT_small.dcm";

std::string bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string received(dicom::IncomingStore& store, const std::string& bytes) {
    const std::string tmp = store.temporaryPath();
    std::ofstream(tmp, std::ios::binary | std::ios::trunc) << bytes;
    return tmp;
}
}  // namespace

TEST(IncomingStore, TwoStoresAtOnceNeverShareATemporaryName) {
    test::TempDir dir;
    dicom::IncomingStore a(dir.path().string()), b(dir.path().string());
    std::set<std::string> names;
    std::mutex m;
    auto take = [&](dicom::IncomingStore& s) {
        for (int i = 0; i < 500; ++i) {
            const std::string n = s.temporaryPath();
            std::lock_guard<std::mutex> lock(m);
            names.insert(n);
        }
    };
    std::thread t1(take, std::ref(a)), t2(take, std::ref(b)), t3(take, std::ref(a));
    t1.join(), t2.join(), t3.join();
    EXPECT_EQ(names.size(), 1500u);
    for (const auto& n : names) EXPECT_TRUE(fs::is_regular_file(n)) << "created exclusively by temporaryPath()";
}

TEST(IncomingStore, SameInstanceAgainIsANoOpAndDifferentBytesAreSetAside) {
    test::TempDir dir;
    dicom::IncomingStore store(dir.path().string());
    const std::string original = bytesOf(ctSmall);
    ASSERT_FALSE(original.empty());
    const auto first = store.finalize(received(store, original));
    ASSERT_TRUE(fs::exists(first.path));
    const auto again = store.finalize(received(store, original));
    EXPECT_EQ(again.path, first.path);
    EXPECT_EQ(bytesOf(first.path), original);
    std::string other = original;
    other[other.size() - 1] = char(other.back() ^ 0x5a);  // another pixel under the same UID
    try {
        store.finalize(received(store, other));
        FAIL() << "a different object replaced or joined the stored one silently";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("arrived again with different content"), std::string::npos) << e.what();
    }
    EXPECT_EQ(bytesOf(first.path), original) << "the stored instance was replaced";
    std::size_t aside = 0;
    for (const auto& e : fs::directory_iterator(dir.path() / ".conflicts")) aside += bytesOf(e.path().string()) == other;
    EXPECT_EQ(aside, 1u);
    std::size_t left = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path() / ".incoming")) ++left;
    EXPECT_EQ(left, 0u) << "temporary files left behind";
}

TEST(IncomingStore, ImportingTheStorageFolderReadsItsInstancesNotItsBookkeeping) {
    // A storage folder as receives leave it: one instance filed, another object under its UID
    // set aside, a receive cut off half-way (its part left in .incoming), and the list of the
    // databases sharing the folder.
    test::TempDir dir;
    const std::string storage = dir.file("storage");
    dicom::IncomingStore store(storage);
    const std::string original = bytesOf(ctSmall);
    const auto filed = store.finalize(received(store, original));
    std::string other = original;
    other[other.size() - 1] = char(other.back() ^ 0x5a);
    EXPECT_THROW(store.finalize(received(store, other)), core::Error);
    (void)received(store, original.substr(0, original.size() / 2));  // the interrupted one
    dicom::StorageOwners::add(storage, dir.file("a.sqlite"));
    core::JobContext job;
    const auto scan = dicom::DicomScanner::scan({storage}, job);
    ASSERT_EQ(scan.instances.size(), 1u);
    EXPECT_EQ(scan.instances[0].path, filed.path);
    EXPECT_EQ(scan.notDicom, 0u) << "the list of databases was counted as a file that is not DICOM";
    EXPECT_EQ(scan.broken, 0u) << "a half-received file was read";
    EXPECT_EQ(scan.setAside, 2u);
    EXPECT_EQ(scan.filesSeen, 1u);

    // Folders of those names elsewhere are nobody's bookkeeping: read as any other.
    const std::string plain = dir.file("plain");
    fs::create_directories(plain + "/.conflicts");
    fs::copy_file(ctSmall, plain + "/.conflicts/ct.dcm");
    const auto elsewhere = dicom::DicomScanner::scan({plain}, job);
    EXPECT_EQ(elsewhere.instances.size(), 1u);
    EXPECT_EQ(elsewhere.setAside, 0u);
}

TEST(UidPath, SanitisedUidsNeverCollide) {
    EXPECT_EQ(dicom::UidPath::component("1.2.840.113619.2.55.3"), "1.2.840.113619.2.55.3");
    const std::string a = dicom::UidPath::component("1.2/3"), b = dicom::UidPath::component("1.2\\3");
    EXPECT_NE(a, b);
    EXPECT_EQ(a.find('/'), std::string::npos);
    const std::string longA(100, '1'), longB = std::string(99, '1') + "2";
    EXPECT_NE(dicom::UidPath::component(longA), dicom::UidPath::component(longB));
    EXPECT_LE(dicom::UidPath::component(longA).size(), 64u);
    for (const char* hostile : {"", ".", "..", "../../etc"}) {
        const std::string c = dicom::UidPath::component(hostile);
        EXPECT_TRUE(c != "." && c != ".." && !c.empty() && c.find('/') == std::string::npos) << hostile << " -> " << c;
    }
}

TEST(AtomicFileWriter, TwoWritersOfOneTargetNeverShareATemporaryFile) {
    test::TempDir dir;
    const std::string target = dir.file("out.bin");
    core::AtomicFileWriter a(target), b(target);
    const std::string x(100000, 'x'), y(50000, 'y');
    a.append(x.data(), x.size());
    b.append(y.data(), y.size());
    b.commit();
    EXPECT_EQ(bytesOf(target), y);
    a.commit();
    EXPECT_EQ(bytesOf(target), x) << "a's bytes mixed with b's";
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}
