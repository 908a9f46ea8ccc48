// The DICOMweb client against Orthanc with its DICOMweb plugin (Debian's orthanc-dicomweb),
// checked against the same archive's DIMSE answers (C-FIND, C-GET), and against a small HTTP
// server in the test that answers with each kind of broken or hostile reply. Also: a study of
// three series retrieved with several associations at once (C-GET, C-MOVE, WADO-RS) is complete
// and byte-identical.
#include <gtest/gtest.h>

#include <algorithm>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <thread>
#include <tuple>

#include "core/base/Error.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomWebClient.h"
#include "dicom/PacsClient.h"
#include "dicom/RetrieveJob.h"
#include "dicom/StudyDatabase.h"
#include "tests/support/FakeHttpServer.h"
#include "tests/support/PacsFixtures.h"
#include "tests/support/PacsPeer.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
using Row = std::tuple<std::string, std::string, std::string, std::string, std::string, std::string, int, int>;

Row rowOf(const dicom::QueryResult& r) {
    return {r.patientName, r.patientId, r.studyUid, r.studyDate, r.seriesUid, r.sopInstanceUid,
            r.level == dicom::QueryLevel::Image ? r.instanceNumber : r.seriesNumber, r.numberOfInstances};
}

std::multiset<Row> rows(dicom::PacsClient& c, dicom::QueryLevel level, const dicom::QueryKeys& k) {
    std::multiset<Row> out;
    c.find(level, k, [&](const dicom::QueryResult& r) {
        out.insert(rowOf(r));
        return true;
    });
    return out;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

/// Files left anywhere under the storage folder (a half-written one would be here).
std::vector<std::string> filesUnder(const std::string& dir) {
    std::vector<std::string> out;
    std::error_code ec;
    for (auto it = std::filesystem::recursive_directory_iterator(dir, ec); it != std::filesystem::end(it); ++it)
        if (it->is_regular_file()) out.push_back(it->path().string());
    return out;
}

class DicomWebPeer : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir();
        peer_ = new test::PacsPeer(test::PacsPeer::Kind::OrthancDicomWeb);
        try {
            peer_->start();
            seeded_ = new test::Seeded(test::makeStudies(dir_->file("seed")));
            peer_->seed(seeded_->files);
        } catch (const std::exception& e) {
            peerError_ = e.what();
        }
    }
    void SetUp() override {
        if (!peerError_.empty())
            FAIL() << "Orthanc with its DICOMweb plugin did not start (installer/install-deps.sh installs "
                      "orthanc-dicomweb): " << peerError_;
    }
    static void TearDownTestSuite() {
        delete peer_;
        delete seeded_;
        delete dir_;
    }
    static dicom::PacsClient dimse() {
        const auto s = peer_->webSettings();
        return dicom::PacsClient(s.local, s.node("peer"));
    }
    static dicom::PacsClient web() {
        const auto s = peer_->webSettings();
        return dicom::PacsClient(s.local, s.node("web"));
    }
    static test::TempDir* dir_;
    static test::PacsPeer* peer_;
    static test::Seeded* seeded_;
    static std::string peerError_;
};
test::TempDir* DicomWebPeer::dir_ = nullptr;
test::PacsPeer* DicomWebPeer::peer_ = nullptr;
test::Seeded* DicomWebPeer::seeded_ = nullptr;
std::string DicomWebPeer::peerError_;
}  // namespace

TEST_F(DicomWebPeer, EchoIsAQidoSearch) { EXPECT_NO_THROW(web().echo()); }

// QIDO-RS and C-FIND on the same archive give the same answers at each level, with
// wildcards, date ranges (open at either end) and modality.
TEST_F(DicomWebPeer, QidoAtEachLevelEqualsCFind) {
    auto d = dimse();
    auto w = web();
    using L = dicom::QueryLevel;
    std::vector<std::pair<L, dicom::QueryKeys>> cases;
    cases.push_back({L::Study, {}});
    dicom::QueryKeys k;
    k.patientName = "DOE*";
    cases.push_back({L::Study, k});
    k = {};
    k.patientName = "R?E^RICHARD";
    cases.push_back({L::Study, k});
    k = {};
    k.studyDate = "20240101-";
    cases.push_back({L::Study, k});
    k.studyDate = "-20231231";
    cases.push_back({L::Study, k});
    k.studyDate = "20231101-20231130";
    cases.push_back({L::Study, k});
    k = {};
    k.patientId = "P2";
    cases.push_back({L::Study, k});
    k = {};
    k.studyUid = seeded_->studyA;
    cases.push_back({L::Series, k});
    k.modality = "CT";
    cases.push_back({L::Series, k});
    k = {};
    k.studyUid = seeded_->studyA;
    k.seriesUid = seeded_->seriesA2;
    cases.push_back({L::Image, k});
    for (const auto& [level, keys] : cases) {
        const auto expected = rows(d, level, keys), got = rows(w, level, keys);
        EXPECT_FALSE(expected.empty()) << "level " << int(level) << " " << keys.patientName << keys.studyDate;
        EXPECT_EQ(got, expected) << "level " << int(level) << " patient '" << keys.patientName << "' date '"
                                 << keys.studyDate << "' modality '" << keys.modality << "'";
    }
    dicom::QueryKeys none;
    none.patientName = "NOBODY*";
    EXPECT_TRUE(rows(w, L::Study, none).empty());
}

// A series by WADO-RS: the same instances as C-GET brings, each dataset byte for byte (the
// stored transfer syntax is asked for), filed in the same place, nothing left half-written.
TEST_F(DicomWebPeer, WadoSeriesIsByteIdenticalToCGet) {
    test::TempDir out;
    std::vector<std::string> viaWeb, viaGet;
    const auto pw = web().get(seeded_->studyA, seeded_->seriesA1, out.file("web"),
                              [&](const dicom::DicomInstance& in) { viaWeb.push_back(in.path); }, {});
    const auto pg = dimse().get(seeded_->studyA, seeded_->seriesA1, out.file("dimse"),
                                [&](const dicom::DicomInstance& in) { viaGet.push_back(in.path); }, {});
    EXPECT_EQ(pw.received, 20);
    EXPECT_EQ(pg.received, 20);
    const auto byWeb = test::bySop(viaWeb), get = test::bySop(viaGet), originals = test::bySop(seeded_->files);
    ASSERT_EQ(byWeb.size(), 20u);
    for (const auto& [sop, path] : get) {
        ASSERT_TRUE(byWeb.count(sop)) << sop;
        EXPECT_EQ(test::datasetBytes(byWeb.at(sop)), test::datasetBytes(path)) << sop;
        EXPECT_EQ(test::datasetBytes(byWeb.at(sop)), test::datasetBytes(originals.at(sop))) << sop;
        EXPECT_EQ(std::filesystem::relative(byWeb.at(sop), out.file("web")),
                  std::filesystem::relative(path, out.file("dimse")));
    }
    EXPECT_TRUE(std::filesystem::is_empty(out.file("web/.incoming")));
    // Chosen instances only (what a retrieve-again asks for).
    test::TempDir two;
    std::vector<std::string> some;
    const std::vector<std::string> wanted{get.begin()->first, std::next(get.begin(), 3)->first};
    web().get(seeded_->studyA, seeded_->seriesA1, two.file("rx"),
              [&](const dicom::DicomInstance& in) { some.push_back(in.sopInstanceUid); }, {}, wanted);
    EXPECT_EQ(std::set<std::string>(some.begin(), some.end()), std::set<std::string>(wanted.begin(), wanted.end()));
}

// STOW-RS: uploaded files (three requests at once: 230 files, 100 to a request) are then found
// by C-FIND, and retrieved byte-identical by C-GET.
TEST_F(DicomWebPeer, StowThenCFindFindsThem) {
    test::TempDir out;
    dicom::DicomWriteOptions o;
    o.patientName = "STOW^UPLOADED";
    o.patientId = "P9";
    o.studyUid = "1.2.826.0.1.3680043.9.7777.90";
    o.seriesUid = "1.2.826.0.1.3680043.9.7777.91";
    o.modality = "CT";
    const auto files = test::writeSeries(out.file("stow"), {8, 8, 230}, o);
    std::vector<std::size_t> progress;
    EXPECT_EQ(web().store(files, [&](std::size_t n) { progress.push_back(n); }), 230u);
    ASSERT_FALSE(progress.empty());
    EXPECT_EQ(progress.size(), 3u) << "one report per request";
    EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
    EXPECT_EQ(progress.back(), 230u);
    dicom::QueryKeys k;
    k.studyUid = o.studyUid;
    k.seriesUid = o.seriesUid;
    auto d = dimse();
    EXPECT_EQ(rows(d, dicom::QueryLevel::Image, k).size(), 230u);
    std::vector<std::string> back;
    dimse().get(o.studyUid, o.seriesUid, out.file("rx"), [&](const dicom::DicomInstance& in) { back.push_back(in.path); }, {});
    const auto originals = test::bySop(files);
    ASSERT_EQ(back.size(), 230u);
    for (const auto& [sop, path] : test::bySop(back)) EXPECT_EQ(test::datasetBytes(path), test::datasetBytes(originals.at(sop)));
    // A file that is not DICOM is refused before anything is sent.
    std::ofstream(out.file("note.txt")) << "not dicom";
    EXPECT_NE(errorOf([&] { web().store({out.file("note.txt")}, {}); }).find("not a DICOM file"), std::string::npos);
}

// A study of three series retrieved with three associations at once, by C-GET, by C-MOVE and
// by WADO-RS: every series complete, indexed once, built, and byte-identical to what was sent.
TEST_F(DicomWebPeer, ParallelRetrieveOfAThreeSeriesStudyIsCompleteAndByteIdentical) {
    test::TempDir seed;
    dicom::DicomWriteOptions o;
    o.patientName = "THREE^SERIES";
    o.patientId = "P3";
    o.studyUid = "1.2.826.0.1.3680043.9.7777.30";
    o.modality = "CT";
    std::vector<std::string> files;
    for (int i = 1; i <= 3; ++i) {
        o.seriesUid = o.studyUid + "." + std::to_string(i);
        o.seriesNumber = i;
        for (auto& f : test::writeSeries(seed.file("s" + std::to_string(i)), {20, 20, std::uint32_t(6 + 3 * i)}, o))
            files.push_back(f);
    }
    peer_->seed(files);
    const auto originals = test::bySop(files);
    for (const char* how : {"get", "move", "web"}) {
        test::TempDir out;
        auto s = peer_->webSettings();
        s.local.storageDir = out.file("rx");
        s.local.parallelAssociations = 3;
        auto node = s.node(std::string(how) == "web" ? "web" : "peer");
        if (std::string(how) == "move") node.retrieve = dicom::RetrieveMethod::Move;
        dicom::StudyDatabase db(out.file("db.sqlite"));
        dicom::RetrieveJob job(s, node, db, out.file("octrees"));
        core::JobContext ctx;
        const auto result = job.run(o.studyUid, "", true, ctx, {});
        ASSERT_EQ(result.size(), 3u) << how;
        for (const auto& r : result) {
            EXPECT_TRUE(r.retrieved && r.error.empty()) << how << ": " << r.error;
            EXPECT_TRUE(std::filesystem::exists(r.octreePath)) << how << " " << r.seriesUid;
        }
        EXPECT_EQ(db.instanceCount(), files.size()) << how;
        std::size_t identical = 0;
        for (int i = 1; i <= 3; ++i)
            for (const auto& f : db.filesOfSeries(o.studyUid + "." + std::to_string(i))) {
                dicom::DicomInstance in;
                dicom::DicomHeaderReader::read(f, in);
                identical += test::datasetBytes(f) == test::datasetBytes(originals.at(in.sopInstanceUid));
            }
        EXPECT_EQ(identical, files.size()) << how;
    }
}

// ---- a server that answers badly ----------------------------------------------------------

namespace {
dicom::PacsClient fakeClient(const test::FakeHttpServer& server, const std::string& storage, int timeout = 5) {
    dicom::LocalNode local;
    local.storageDir = storage;
    local.timeoutSeconds = timeout;
    local.minFreeBytes = 0;
    dicom::PacsNode n;
    n.name = "fake";
    n.kind = dicom::NodeKind::DicomWeb;
    n.baseUrl = server.url();
    return dicom::PacsClient(local, n);
}

const std::string kStudy = "1.2.3", kSeries = "1.2.3.4";

std::string part(const std::string& boundary, const std::string& body, const std::string& extra = "") {
    return "--" + boundary + "\r\nContent-Type: application/dicom\r\n" + extra + "\r\n" + body + "\r\n";
}

std::string multipart(const std::string& boundary) { return "multipart/related; type=\"application/dicom\"; boundary=" + boundary; }
}  // namespace

TEST(DicomWebFaults, HttpErrorsAreSentences) {
    test::TempDir dir;
    int status = 401;
    test::FakeHttpServer server([&](int s, const std::string&) {
        test::FakeHttpServer::write(s, test::FakeHttpServer::answer(status, "text/plain", "go away"));
    });
    auto c = fakeClient(server, dir.file("rx"));
    const auto find = [&] { c.find(dicom::QueryLevel::Study, {}, {}); };
    EXPECT_NE(errorOf(find).find("refused our credentials (HTTP 401)"), std::string::npos) << errorOf(find);
    status = 403;
    EXPECT_NE(errorOf(find).find("HTTP 403"), std::string::npos);
    status = 404;
    EXPECT_NE(errorOf([&] { c.get(kStudy, kSeries, dir.file("rx"), {}, {}); }).find("not found (HTTP 404)"), std::string::npos);
    test::TempDir seed;
    const auto files = test::writeSeries(seed.file("f"), {8, 8, 2}, {});
    status = 413;
    EXPECT_NE(errorOf([&] { c.store(files, {}); }).find("too large (HTTP 413)"), std::string::npos);
    status = 507;
    const std::string full = errorOf([&] { c.store(files, {}); });
    EXPECT_NE(full.find("storage is full (HTTP 507)"), std::string::npos) << full;
    EXPECT_NE(full.find("go away"), std::string::npos) << "the server's own words are kept: " << full;
    EXPECT_TRUE(filesUnder(dir.file("rx")).empty());
}

TEST(DicomWebFaults, AnswersThatAreNotADicomJsonModelAreRefused) {
    test::TempDir dir;
    std::string body;
    test::FakeHttpServer server([&](int s, const std::string&) {
        test::FakeHttpServer::write(s, test::FakeHttpServer::answer(200, "application/dicom+json", body));
    });
    auto c = fakeClient(server, dir.file("rx"));
    const auto find = [&] { c.find(dicom::QueryLevel::Study, {}, {}); };
    body = "<html>login</html>";
    EXPECT_NE(errorOf(find).find("not JSON"), std::string::npos) << errorOf(find);
    body = "{\"studies\": []}";
    EXPECT_NE(errorOf(find).find("not a DICOM JSON model"), std::string::npos) << errorOf(find);
    body = "[1, 2]";
    EXPECT_NE(errorOf(find).find("other than DICOM datasets"), std::string::npos) << errorOf(find);
    body = "[{\"00100010\": {\"vr\": \"PN\", \"Value\": \"DOE\"}}]";
    EXPECT_NE(errorOf(find).find("not an array"), std::string::npos) << errorOf(find);
    body = "[{\"0020000D\": {\"vr\": \"UI\", \"Value\": [\"1.2.3\"]}, \"00100010\": {\"vr\": \"PN\", \"Value\": "
           "[{\"Alphabetic\": \"DOE^JO\"}]}, \"00201208\": {\"vr\": \"IS\", \"Value\": [12]}}]";
    std::vector<dicom::QueryResult> got;
    c.find(dicom::QueryLevel::Study, {}, [&](const dicom::QueryResult& r) {
        got.push_back(r);
        return true;
    });
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].patientName, "DOE^JO");
    EXPECT_EQ(got[0].studyUid, "1.2.3");
    EXPECT_EQ(got[0].numberOfInstances, 12);
}

// A server that ignores limit and offset is not asked forever; an answer larger than any query
// answer should be is refused without holding it.
TEST(DicomWebFaults, PagingThatIsIgnoredEndsAndAHugeAnswerIsRefused) {
    test::TempDir dir;
    bool huge = false;
    test::FakeHttpServer server([&](int s, const std::string&) {
        if (!huge) {
            std::string body = "[";
            for (int i = 0; i < dicom::DicomWebClient::kPageSize; ++i)
                body += std::string(i ? "," : "") + "{\"0020000D\": {\"vr\": \"UI\", \"Value\": [\"1.2." +
                        std::to_string(i) + "\"]}}";
            test::FakeHttpServer::write(s, test::FakeHttpServer::answer(200, "application/dicom+json", body + "]"));
            return;
        }
        test::FakeHttpServer::write(s, "HTTP/1.1 200 OK\r\nContent-Type: application/dicom+json\r\nConnection: close\r\n\r\n[");
        const std::string chunk(1 << 20, ' ');
        for (int i = 0; i < 80 && test::FakeHttpServer::write(s, chunk); ++i) {}
    });
    auto c = fakeClient(server, dir.file("rx"));
    EXPECT_EQ(c.find(dicom::QueryLevel::Study, {}, {}), std::size_t(dicom::DicomWebClient::kPageSize));
    EXPECT_EQ(server.requests(), 2) << "the second page brought nothing new: the search ends";
    huge = true;
    const std::string e = errorOf([&] { c.find(dicom::QueryLevel::Study, {}, {}); });
    EXPECT_NE(e.find("larger than 64 MiB"), std::string::npos) << e;
}

// Broken multipart answers: each is a sentence, what was complete is filed, nothing is left
// half-written, and a part that is not DICOM is not filed.
TEST(DicomWebFaults, BrokenMultipartAnswersLeaveNothingHalfWritten) {
    test::TempDir dir, seed;
    const auto files = test::writeSeries(seed.file("f"), {8, 8, 2}, {});
    std::ifstream in(files[0], std::ios::binary);
    const std::string instance((std::istreambuf_iterator<char>(in)), {});
    std::string type, body;
    test::FakeHttpServer server([&](int s, const std::string&) {
        test::FakeHttpServer::write(s, test::FakeHttpServer::answer(200, type, body));
    });
    auto c = fakeClient(server, dir.file("rx"));
    const auto get = [&] { c.get(kStudy, kSeries, dir.file("rx"), {}, {}); };
    struct Case {
        std::string name, type, body, expect;
        std::size_t filed;
    };
    const std::string b = "XyZ";
    const std::vector<Case> cases{
        {"not multipart", "application/dicom+json", "[]", "not a multipart body", 0},
        {"no boundary", "multipart/related; type=\"application/dicom\"", "", "names no boundary", 0},
        {"no opening boundary", multipart(b), "just text", "holds no boundary", 0},
        {"cut after one part", multipart(b), part(b, instance) + "--XyZ\r\nContent-Type: application/dicom\r\n\r\n" +
                                                instance.substr(0, 300), "ended before its closing boundary", 1},
        {"longer than announced", multipart(b),
         part(b, instance, "Content-Length: " + std::to_string(instance.size() - 10) + "\r\n") + "--XyZ--\r\n",
         "longer than the", 0},
        {"not DICOM", multipart(b), part(b, std::string(400, 'x')) + "--XyZ--\r\n", "", 0},
        {"a web page as a part", multipart(b), "--XyZ\r\nContent-Type: text/html\r\n\r\n<html/>\r\n--XyZ--\r\n",
         "not a DICOM instance", 0},
    };
    for (const auto& k : cases) {
        std::filesystem::remove_all(dir.file("rx"));
        type = k.type;
        body = k.body;
        const std::string e = errorOf(get);
        EXPECT_FALSE(e.empty()) << k.name;
        if (!k.expect.empty()) EXPECT_NE(e.find(k.expect), std::string::npos) << k.name << ": " << e;
        EXPECT_NE(e.find(std::to_string(k.filed) + " instances were stored completely"), std::string::npos)
            << k.name << ": " << e;
        std::size_t filed = 0;
        for (const auto& f : filesUnder(dir.file("rx"))) {
            EXPECT_EQ(f.find("/.incoming/"), std::string::npos) << k.name << ": left behind " << f;
            filed += f.find("/.incoming/") == std::string::npos;
        }
        EXPECT_EQ(filed, k.filed) << k.name;
    }
}

TEST(DicomWebFaults, UnreachableAndStalledServersAreExplained) {
    test::TempDir dir;
    dicom::LocalNode local;
    local.storageDir = dir.file("rx");
    local.timeoutSeconds = 2;
    dicom::PacsNode n;
    n.name = "gone";
    n.kind = dicom::NodeKind::DicomWeb;
    n.baseUrl = "http://127.0.0.1:" + std::to_string(test::freePort()) + "/dicom-web";
    const std::string refused = errorOf([&] { dicom::PacsClient(local, n).echo(); });
    EXPECT_NE(refused.find("cannot connect"), std::string::npos) << refused;
    n.baseUrl = "http://no-such-host.invalid/dicom-web";
    const std::string unknown = errorOf([&] { dicom::PacsClient(local, n).echo(); });
    EXPECT_NE(unknown.find("host name is unknown"), std::string::npos) << unknown;
    std::atomic<bool> release{false};  // the server stalls until the client has given up
    test::FakeHttpServer stall([&](int s, const std::string&) {
        test::FakeHttpServer::write(s, "HTTP/1.1 200 OK\r\nContent-Type: application/dicom+json\r\n\r\n[");
        for (int i = 0; i < 300 && !release; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    });
    const auto start = std::chrono::steady_clock::now();
    const std::string stalled = errorOf([&] { fakeClient(stall, dir.file("rx"), 2).find(dicom::QueryLevel::Study, {}, {}); });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    release = true;
    EXPECT_NE(stalled.find("no answer for 2 s"), std::string::npos) << stalled;
    EXPECT_LT(seconds, 8.0) << "the stall is noticed at the timeout (2 s), not when the server gives up (15 s)";
}
