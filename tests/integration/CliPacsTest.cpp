// The command line's PACS commands against a real Orthanc: `pacs add` writes the node table
// that `pacs nodes` lists; `pacs echo`, `pacs find` at each level (checked against what was
// seeded), `pacs send` and `pacs get` (files byte-identical to their sources, indexed, listed by
// `studies`), and a node that does not answer is an error with a sentence and a non-zero exit.
// `listen` files what storescu pushes and stops on SIGTERM.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <thread>

#include "core/base/JobContext.h"
#include "core/volume/PhantomVoxelSource.h"
#include "dicom/DicomSeriesWriter.h"
#include "dicom/StorageOwners.h"
#include "dicom/StudyDatabase.h"
#include "tests/support/PacsPeer.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
const std::string cli = HVX_CLI;

std::string bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

/// The 24×24 16-bit pixels that end each file (Pixel Data is the last element), as a multiset.
std::multiset<std::string> pixelsOf(const std::vector<std::string>& paths) {
    std::multiset<std::string> out;
    for (const auto& p : paths) {
        const std::string all = bytes(p);
        out.insert(all.substr(all.size() - std::min<std::size_t>(all.size(), 24 * 24 * 2)));
    }
    return out;
}

std::vector<std::string> phantomSeries(const std::string& dir, const std::string& patient, const std::string& study,
                                       const std::string& series, std::uint32_t slices) {
    core::PhantomVoxelSource p({24, 24, slices}, 7);
    dicom::DicomWriteOptions o;
    o.patientName = patient;
    o.patientId = patient.substr(0, 4);
    o.studyUid = study;
    o.seriesUid = series;
    o.studyDescription = "CLI PACS";
    o.modality = "CT";
    core::JobContext job;
    return dicom::DicomSeriesWriter::write(p, dir, o, job);
}
}  // namespace

TEST(CliPacs, AddListEchoFindSendAndGetAgainstOrthanc) {
    test::TempDir dir;
    test::PacsPeer peer(test::PacsPeer::Kind::Orthanc);
    ASSERT_NO_THROW(peer.start());
    const std::string study = "1.2.826.0.1.3680043.9.7777.500", series = "1.2.826.0.1.3680043.9.7777.501";
    const auto seeded = phantomSeries(dir.file("seed"), "CLI^SEEDED", study, series, 6);
    peer.seed(seeded);
    const std::string config = " --config " + dir.file("pacs.json");
    // The local node: our AE title as Orthanc knows it, receiving under the test folder.
    const auto settings = peer.settings();
    auto r = test::runCommand(cli + " pacs add orthanc --ae " + peer.aeTitle() + " --host 127.0.0.1 --port " +
                              std::to_string(peer.dicomPort()) + " --local-ae " + settings.local.aeTitle +
                              " --local-port " + std::to_string(settings.local.port) + " --storage " + dir.file("rx") +
                              config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " pacs nodes" + config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("* orthanc"), std::string::npos) << "the first node becomes the default:\n" << r.output;
    EXPECT_NE(r.output.find("127.0.0.1:" + std::to_string(peer.dicomPort())), std::string::npos) << r.output;

    r = test::runCommand(cli + " pacs echo orthanc" + config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("C-ECHO to orthanc"), std::string::npos) << r.output;

    r = test::runCommand(cli + " pacs find orthanc --patient 'CLI*'" + config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("CLI^SEEDED"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(study), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1 results"), std::string::npos) << r.output;
    r = test::runCommand(cli + " pacs find orthanc --level image --study " + study + " --series " + series + config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("6 results"), std::string::npos) << r.output;
    r = test::runCommand(cli + " pacs find orthanc --patient 'NOBODY*'" + config);
    EXPECT_NE(r.output.find("0 results"), std::string::npos) << r.output;

    // send: a second patient's series goes to the PACS, then is found there.
    const auto sent = phantomSeries(dir.file("send"), "CLI^SENT", study + "1", series + "1", 4);
    std::string files;
    for (const auto& f : sent) files += " " + f;
    r = test::runCommand(cli + " pacs send orthanc" + files + config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("sent 4 files, 4 accepted"), std::string::npos) << r.output;
    r = test::runCommand(cli + " pacs find orthanc --patient 'CLI^SENT'" + config);
    EXPECT_NE(r.output.find(study + "1"), std::string::npos) << r.output;

    // get: the seeded series arrives byte-identical, indexed in the database `studies` reads.
    const std::string db = " --db " + dir.file("db/studies.sqlite");
    r = test::runCommand(cli + " pacs get orthanc " + study + " --no-build" + db + config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("6 completed, 0 failed"), std::string::npos) << r.output;
    dicom::StudyDatabase database(dir.file("db/studies.sqlite"));
    const auto got = database.filesOfSeries(series);
    ASSERT_EQ(got.size(), seeded.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_TRUE(std::filesystem::exists(got[i])) << got[i];
        EXPECT_EQ(got[i].rfind(dir.file("rx") + "/", 0), 0u) << "stored under --storage: " << got[i];
    }
    // Pixel Data ends each file: every seeded image's pixels arrived, once each.
    EXPECT_TRUE(pixelsOf(seeded) == pixelsOf(got)) << "the received files carry the seeded pixels";
    r = test::runCommand(cli + " studies" + db);
    EXPECT_NE(r.output.find("CLI^SEEDED"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("6 images"), std::string::npos) << r.output;

    // A node nobody answers on: a sentence and a non-zero exit.
    ASSERT_EQ(test::runCommand(cli + " pacs add nobody --ae NOBODY --host 127.0.0.1 --port " +
                               std::to_string(test::freePort()) + config)
                  .exitCode,
              0);
    r = test::runCommand(cli + " pacs echo nobody" + config);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("connection refused"), std::string::npos) << r.output;
}

// Every association Holovox opens sets TCP_NODELAY (DCMTK 3.6.7 leaves Nagle's algorithm on,
// and each small DIMSE message then waits out a delayed ACK) and TCP_QUICKACK after its reads,
// as strace sees the socket calls;
// and a DICOMweb node is added, listed and searched like a DIMSE one.
TEST(CliPacs, EveryAssociationSetsTcpNoDelayAndDicomWebNodesWorkAlike) {
    test::TempDir dir;
    test::PacsPeer peer(test::PacsPeer::Kind::OrthancDicomWeb);
    ASSERT_NO_THROW(peer.start());
    const std::string study = "1.2.826.0.1.3680043.9.7777.600", series = "1.2.826.0.1.3680043.9.7777.601";
    const auto seeded = phantomSeries(dir.file("seed"), "CLI^NODELAY", study, series, 3);
    const std::string config = " --config " + dir.file("pacs.json");
    const auto settings = peer.settings();
    auto r = test::runCommand(cli + " pacs add dimse --ae " + peer.aeTitle() + " --host 127.0.0.1 --port " +
                              std::to_string(peer.dicomPort()) + " --local-port " + std::to_string(settings.local.port) +
                              " --storage " + dir.file("rx") + config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::string files;
    for (const auto& f : seeded) files += " " + f;
    const std::string strace = "strace -f -e trace=setsockopt ";
    for (const std::string& op : {std::string(" pacs echo dimse"), " pacs send dimse" + files,
                                  " pacs get dimse " + study + " --no-build --db " + dir.file("db.sqlite")}) {
        r = test::runCommand(strace + cli + op + config);
        ASSERT_EQ(r.exitCode, 0) << op << "\n" << r.output;
        EXPECT_NE(r.output.find("TCP_NODELAY, [1]"), std::string::npos) << op << ": no TCP_NODELAY\n" << r.output;
        // Orthanc keeps Nagle on: our ACKs go at once, after every read.
        EXPECT_NE(r.output.find("TCP_QUICKACK, [1]"), std::string::npos) << op << ": no TCP_QUICKACK\n" << r.output;
    }
    // The same archive as a DICOMweb node.
    r = test::runCommand(cli + " pacs add web --dicomweb " + peer.dicomWebUrl() + config);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " pacs nodes" + config);
    EXPECT_NE(r.output.find("web              DICOMweb " + peer.dicomWebUrl()), std::string::npos) << r.output;
    r = test::runCommand(cli + " pacs echo web" + config);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand(cli + " pacs find web --patient 'CLI^NO*'" + config);
    EXPECT_NE(r.output.find(study), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1 results"), std::string::npos) << r.output;
    r = test::runCommand(cli + " pacs move web " + study + config);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("retrieves by WADO-RS"), std::string::npos) << r.output;
    r = test::runCommand(cli + " pacs get web " + study + " --db " + dir.file("db2.sqlite") + config);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("3 completed, 0 failed"), std::string::npos) << r.output;
    for (const char* bad : {" --dicomweb pacs:8042", " --dicomweb http://h/x --token t --user u"}) {
        r = test::runCommand(cli + " pacs add bad" + bad + config);
        EXPECT_NE(r.exitCode, 0) << bad;
    }
}

// `holovox-cli listen`, the storage SCP in the foreground as a reading room runs it for the
// modalities that push to it: DCMTK's storescu sends a series under an allowed calling AE
// title, and every image arrives with its pixels, is said on stdout and indexed in the
// database `studies` reads; a calling AE title not allowed is refused and files nothing;
// SIGTERM stops it, saying how many it received, and frees the port.
TEST(CliPacs, ListenFilesWhatAModalityPushesAndStopsOnSigterm) {
    test::TempDir dir;
    const auto files = phantomSeries(dir.file("push"), "CLI^PUSHED", "1.2.826.0.1.3680043.9.7777.600",
                                     "1.2.826.0.1.3680043.9.7777.601", 5);
    const std::uint16_t port = test::freePort();
    const std::string db = dir.file("listen.sqlite"), log = dir.file("listen.log");
    auto r = test::runCommand(cli + " listen --port " + std::to_string(port) + " --ae HVXLISTEN --storage " +
                              dir.file("in") + " --db " + db + " --allow MODALITY1 --config " + dir.file("none.json") +
                              " > " + log + " 2>&1 & echo $!");
    const pid_t pid = pid_t(std::stol(r.output));
    ASSERT_GT(pid, 0);
    const auto stop = [pid] {  // SIGTERM, then wait up to 20 s for the process to be gone
        ::kill(pid, SIGTERM);
        for (int i = 0; i < 200 && ::kill(pid, 0) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        return ::kill(pid, 0) != 0;
    };
    if (!test::waitForPort(port, 20)) {
        stop();
        FAIL() << "listen did not open port " << port << ": " << bytes(log);
    }
    std::string send = "storescu -aet MODALITY1 -aec HVXLISTEN 127.0.0.1 " + std::to_string(port);
    for (const auto& f : files) send += " " + f;
    r = test::runCommand(send + " 2>&1");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    r = test::runCommand("storescu -aet INTRUDER -aec HVXLISTEN 127.0.0.1 " + std::to_string(port) + " " + files[0] +
                         " 2>&1");
    EXPECT_NE(r.exitCode, 0) << "a calling AE title not allowed is refused: " << r.output;
    ASSERT_TRUE(stop()) << "listen did not stop on SIGTERM: " << bytes(log);
    EXPECT_FALSE(test::waitForPort(port, 0.5)) << "the port is free again";

    const std::string said = bytes(log);
    EXPECT_NE(said.find("listening on port " + std::to_string(port)), std::string::npos) << said;
    std::size_t lines = 0;
    for (auto at = said.find("received CT "); at != std::string::npos; at = said.find("received CT ", at + 1)) ++lines;
    EXPECT_EQ(lines, files.size()) << said;
    EXPECT_NE(said.find("stopped after 5 instances"), std::string::npos) << said;
    std::vector<std::string> stored;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir.file("in")))
        if (e.is_regular_file() && e.path().filename() != dicom::StorageOwners::kListName) stored.push_back(e.path().string());
    ASSERT_EQ(stored.size(), files.size());
    // The listener lists its database in the storage folder (StudyRemoval keeps what another indexes).
    EXPECT_EQ(dicom::StorageOwners::othersThan(dir.file("in"), dir.file("none.sqlite")).size(), 1u);
    EXPECT_TRUE(pixelsOf(files) == pixelsOf(stored)) << "the stored files carry the pushed pixels";
    r = test::runCommand(cli + " studies --db " + db);
    EXPECT_NE(r.output.find("CLI^PUSHED"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("5 images"), std::string::npos) << r.output;
}
