// The pieces of the DICOMweb client that read what a server sends: the multipart reader (fed
// in pieces split at every byte, so that a boundary across two reads is found), base URLs, and
// the DICOM JSON model of QIDO-RS and STOW-RS answers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>

using namespace std::string_literals;

#include "core/base/Error.h"
#include "dicom/DicomJson.h"
#include "dicom/DicomWebUrl.h"
#include "dicom/MultipartReader.h"
#include "dicom/PacsSettings.h"
#include "tests/support/ErrorOf.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
struct Collect : dicom::MultipartReader::Sink {
    std::vector<std::string> parts;
    std::vector<std::map<std::string, std::string>> headers;
    bool open = false;
    void beginPart(const std::map<std::string, std::string>& h) override {
        parts.emplace_back();
        headers.push_back(h);
        open = true;
    }
    void partData(const char* d, std::size_t n) override { parts.back().append(d, n); }
    void endPart() override { open = false; }
};

using test::errorOf;
}  // namespace

TEST(MultipartReader, PartsAreExactWhereverTheBodyIsSplit) {
    // Bodies that hold CR, LF, dashes and a near-boundary, a preamble, transport padding and an
    // epilogue, as RFC 2046 allows.
    const std::string one = "\r\n--Xz a--Xy\r\n\r\n-\r\n--X binary\0\1\2 end\r"s, two = "--", three;
    const std::string body = "preamble to ignore\r\n--Xy  \r\nContent-Type: application/dicom\r\nX-Other: 1\r\n\r\n" + one +
                             "\r\n--Xy\r\ncontent-type: application/dicom\r\n\r\n" + two + "\r\n--Xy\r\n\r\n" + three +
                             "\r\n--Xy--\r\nepilogue";
    for (std::size_t cut = 0; cut <= body.size(); ++cut) {
        Collect c;
        dicom::MultipartReader r("Xy", c, 1 << 20);
        r.feed(body.data(), cut);
        r.feed(body.data() + cut, body.size() - cut);
        ASSERT_NO_THROW(r.finish()) << cut;
        ASSERT_EQ(c.parts.size(), 3u) << cut;
        EXPECT_EQ(c.parts[0], one) << cut;
        EXPECT_EQ(c.parts[1], two) << cut;
        EXPECT_EQ(c.parts[2], three) << cut;
        EXPECT_EQ(c.headers[0].at("content-type"), "application/dicom");
        EXPECT_FALSE(c.open);
    }
    // Byte by byte.
    Collect c;
    dicom::MultipartReader r("Xy", c, 1 << 20);
    for (char ch : body) r.feed(&ch, 1);
    EXPECT_NO_THROW(r.finish());
    EXPECT_EQ(c.parts.size(), 3u);
}

TEST(MultipartReader, MalformedBodiesAreSentences) {
    Collect c;
    const auto run = [&](const std::string& body, std::uint64_t cap = 1 << 20) {
        return errorOf([&] {
            dicom::MultipartReader r("B", c, cap);
            r.feed(body.data(), body.size());
            r.finish();
        });
    };
    EXPECT_NE(run("").find("holds no boundary"), std::string::npos);
    EXPECT_NE(run("--B\r\nA: b\r\n\r\nxx").find("ended before its closing boundary"), std::string::npos);
    EXPECT_NE(run("--B\r\n" + std::string(20000, 'h')).find("headers without an end"), std::string::npos);
    EXPECT_NE(run("--B\r\nContent-Length: 2\r\n\r\nabc\r\n--B--").find("longer than the 2 bytes"), std::string::npos);
    EXPECT_NE(run("--B\r\nContent-Length: 5\r\n\r\nabc\r\n--B--").find("not the 5"), std::string::npos);
    EXPECT_NE(run("--B\r\nContent-Length: x\r\n\r\nabc\r\n--B--").find("unreadable Content-Length"), std::string::npos);
    EXPECT_NE(run("--B\r\n\r\n" + std::string(3000, 'a') + "\r\n--B--", 1000).find("larger than"), std::string::npos);
    EXPECT_NE(run("--Bjunk\r\n\r\n\r\n--B--").find("malformed boundary line"), std::string::npos);
}

TEST(MultipartReader, BoundaryOfContentTypes) {
    EXPECT_EQ(dicom::MultipartReader::boundaryOf("multipart/related; type=\"application/dicom\"; boundary=abc"), "abc");
    EXPECT_EQ(dicom::MultipartReader::boundaryOf("Multipart/Related;Boundary=\"a b;c\"; type=x"), "a b;c");
    EXPECT_NE(errorOf([] { dicom::MultipartReader::boundaryOf("application/json"); }).find("not a multipart"), std::string::npos);
    EXPECT_NE(errorOf([] { dicom::MultipartReader::boundaryOf("multipart/related"); }).find("names no boundary"), std::string::npos);
    EXPECT_NE(errorOf([] { dicom::MultipartReader::boundaryOf("multipart/related; boundary=\"abc"); }).find("not closed"),
              std::string::npos);
}

TEST(DicomWebUrl, ParsesAndRefuses) {
    const auto u = dicom::DicomWebUrl::parse("HTTPS://pacs.example.org:8443/dicom-web/", "x");
    EXPECT_EQ(u.scheme, "https");
    EXPECT_EQ(u.host, "pacs.example.org");
    EXPECT_EQ(u.port, 8443);
    EXPECT_EQ(u.path, "/dicom-web");
    EXPECT_EQ(dicom::DicomWebUrl::parse("http://[::1]/wado", "x").host, "::1");
    EXPECT_EQ(dicom::DicomWebUrl::parse("http://h", "x").port, 80);
    EXPECT_EQ(dicom::DicomWebUrl::root("http://h/dicom-web//"), "http://h/dicom-web");
    for (const char* bad : {"pacs:8042", "ftp://h/x", "http:///x", "http://h:0/", "http://h:99999/", "http://h:12a/",
                            "http://user:pw@h/x", "http://h/x?limit=1"})
        EXPECT_THROW(dicom::DicomWebUrl::check(bad, "node"), core::Error) << bad;
    EXPECT_EQ(dicom::DicomWebUrl::encode("DOE^J* ?&=%/é"), "DOE^J*%20?%26%3D%25%2F%C3%A9");
}

TEST(DicomJson, StowOutcomeCountsStoredAndFailed) {
    const std::string body =
        "{\"00081199\": {\"vr\": \"SQ\", \"Value\": [{\"00081155\": {\"vr\": \"UI\", \"Value\": [\"1.1\"]}}, "
        "{\"00081155\": {\"vr\": \"UI\", \"Value\": [\"1.2\"]}}]}, \"00081198\": {\"vr\": \"SQ\", \"Value\": "
        "[{\"00081155\": {\"vr\": \"UI\", \"Value\": [\"1.3\"]}, \"00081197\": {\"vr\": \"US\", \"Value\": [42752]}}]}}";
    const auto o = dicom::DicomJson::stowOutcome(body, "x");
    EXPECT_EQ(o.stored, (std::vector<std::string>{"1.1", "1.2"}));
    ASSERT_EQ(o.failed.size(), 1u);
    EXPECT_EQ(o.failed[0], "1.3 (reason 0xA700)");
    EXPECT_THROW(dicom::DicomJson::stowOutcome("[1]", "x"), core::Error);
    EXPECT_TRUE(dicom::DicomJson::queryResults(" \n", dicom::QueryLevel::Study, "x").empty());
}

// A person name's three groups (PS3.18 F.2.2) read as C-FIND reads them, joined by "=" (a
// Japanese name had kept its alphabetic group alone); a group that is not a string is a sentence.
TEST(DicomJson, PersonNamesKeepTheirIdeographicAndPhoneticGroups) {
    const auto name = [](const std::string& pn) {
        const auto r = dicom::DicomJson::queryResults("[{\"00100010\": {\"vr\": \"PN\", \"Value\": [" + pn + "]}}]",
                                                      dicom::QueryLevel::Study, "x");
        return r.at(0).patientName;
    };
    EXPECT_EQ(name("{\"Alphabetic\": \"Yamada^Tarou\", \"Ideographic\": \"\u5c71\u7530^\u592a\u90ce\", "
                   "\"Phonetic\": \"\u3084\u307e\u3060^\u305f\u308d\u3046\"}"),
              "Yamada^Tarou=\u5c71\u7530^\u592a\u90ce=\u3084\u307e\u3060^\u305f\u308d\u3046");
    EXPECT_EQ(name("{\"Alphabetic\": \"Wang^XiaoDong\", \"Ideographic\": \"\u738b^\u5c0f\u6771\", \"Phonetic\": \"\"}"),
              "Wang^XiaoDong=\u738b^\u5c0f\u6771");
    EXPECT_EQ(name("{\"Ideographic\": \"\u738b\"}"), "=\u738b");
    EXPECT_EQ(name("{\"Alphabetic\": \"DOE^JANE\"}"), "DOE^JANE");
    EXPECT_EQ(name("{}"), "");
    try {
        name("{\"Alphabetic\": 7}");
        ADD_FAILURE() << "a number as a name group was taken";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("Alphabetic group of the person name 00100010 is not a string"), std::string::npos)
            << e.what();
    }
}

// A DICOMweb node, the PDU size and the parallel associations survive a save and a load; the
// file with credentials is readable by its owner only; bad values are refused naming the field.
TEST(PacsSettings, DicomWebNodesAndNetworkSettingsRoundTrip) {
    test::TempDir dir;
    const std::string path = dir.file("cfg/pacs.json");
    dicom::PacsSettings s;
    s.local.maxPdu = 65536;
    s.local.parallelAssociations = 5;
    dicom::PacsNode d;
    d.name = "dimse";
    d.aeTitle = "PACS";
    d.host = "10.0.0.1";
    d.port = 104;
    d.maxPdu = 32768;
    s.nodes.push_back(d);
    dicom::PacsNode w;
    w.name = "web";
    w.kind = dicom::NodeKind::DicomWeb;
    w.baseUrl = "https://pacs.example.org/dicom-web";
    w.username = "reader";
    w.password = "secret";
    w.tlsVerify = false;
    s.nodes.push_back(w);
    s.save(path);
    EXPECT_EQ(std::filesystem::status(path).permissions() & std::filesystem::perms::all,
              std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
    const auto back = dicom::PacsSettings::load(path);
    EXPECT_EQ(back.local.maxPdu, 65536u);
    EXPECT_EQ(back.local.parallelAssociations, 5);
    EXPECT_EQ(back.node("dimse").maxPdu, 32768u);
    const auto& b = back.node("web");
    EXPECT_EQ(b.kind, dicom::NodeKind::DicomWeb);
    EXPECT_EQ(b.baseUrl, w.baseUrl);
    EXPECT_EQ(b.username, "reader");
    EXPECT_EQ(b.password, "secret");
    EXPECT_FALSE(b.tlsVerify);
    const auto refused = [&](const std::string& json) {
        std::ofstream(path) << json;
        return errorOf([&] { dicom::PacsSettings::load(path); });
    };
    EXPECT_NE(refused(R"({"local": {"maxPdu": 100}})").find("maxPdu 100 must be 4096 to 131072"), std::string::npos);
    EXPECT_NE(refused(R"({"local": {"parallelAssociations": 0}})").find("parallelAssociations"), std::string::npos);
    EXPECT_NE(refused(R"({"local": {}, "nodes": [{"name": "w", "kind": "dicomweb", "url": "ftp://x"}]})").find("node 'w'"),
              std::string::npos);
    EXPECT_NE(refused(R"({"local": {}, "nodes": [{"name": "w", "kind": "dicomweb"}]})").find("malformed"), std::string::npos);
}
