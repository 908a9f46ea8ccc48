#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <signal.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <thread>

#include "core/base/Error.h"
#include "core/volume/PhantomVoxelSource.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomSeriesWriter.h"
#include "dicom/PacsClient.h"
#include "dicom/StorageServer.h"
#include "tests/support/PacsPeer.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/StorageListener.h"
#include "tests/support/TestCertificates.h"

using namespace hvx;

namespace {
std::vector<std::string> series(const std::string& dir, dicom::DicomWriteOptions o = {}) {
    core::PhantomVoxelSource p({16, 16, 4}, 2);
    core::JobContext job;
    return dicom::DicomSeriesWriter::write(p, dir, o, job);
}

std::size_t filesUnder(const std::string& dir) {
    std::size_t n = 0;
    std::error_code ec;
    for (const auto& f : std::filesystem::recursive_directory_iterator(dir, ec)) n += f.is_regular_file();
    return n;
}

void sendRaw(std::uint16_t port, const std::string& bytes) {
    const int s = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(port);
    ASSERT_EQ(::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    ::send(s, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    char buf[256];
    timeval tv{3, 0};
    ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    while (::recv(s, buf, sizeof buf, 0) > 0) {}
    ::close(s);
}

using Listener = test::StorageListener;
}  // namespace

TEST(StorageServer, AcceptsPushesAndEchoFromAllowedCallers) {
    Listener l;
    test::TempDir src;
    const auto files = series(src.file("s"));
    EXPECT_EQ(l.store("MODALITY1", files), "");
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    EXPECT_EQ(l.server->received(), 4u);
    EXPECT_EQ(filesUnder(l.local.storageDir), 4u);
    {
        std::lock_guard lock(l.mutex);
        ASSERT_EQ(l.got.size(), 4u);
        for (const auto& in : l.got) EXPECT_EQ(in.path.rfind(l.local.storageDir + "/", 0), 0u);
    }
    const auto echo = test::runCommand("echoscu -aet MODALITY1 -aec HOLOVOX 127.0.0.1 " + std::to_string(l.local.port));
    EXPECT_EQ(echo.exitCode, 0) << echo.output;
}

TEST(StorageServer, RefusesCallingAeTitlesNotOnTheAllowList) {
    Listener l;
    test::TempDir src;
    const auto out = l.store("STRANGER", series(src.file("s")));
    EXPECT_NE(out.find("Rejected"), std::string::npos) << out;
    EXPECT_EQ(filesUnder(l.local.storageDir), 0u);
}

// Associations called to another AE title, and a node's AE title calling from an address its
// node entry does not name, are refused before anything is stored.
TEST(StorageServer, RefusesAnotherCalledAeTitleAndANodesTitleFromAnotherAddress) {
    test::TempDir src;
    const auto files = series(src.file("s"));
    {
        Listener l;
        const auto r = test::runCommand("storescu -aet MODALITY1 -aec SOMEONEELSE 127.0.0.1 " +
                                        std::to_string(l.local.port) + " " + files[0] + " 2>&1");
        EXPECT_NE(r.exitCode, 0);
        EXPECT_NE(r.output.find("Called AE Title Not Recognized"), std::string::npos) << r.output;
        EXPECT_EQ(l.server->received(), 0u);
    }
    {
        Listener l({}, [](dicom::StorageServer& s) { s.requireHost("MODALITY1", "192.0.2.7"); });  // TEST-NET-1
        EXPECT_NE(l.store("MODALITY1", files), "");
        EXPECT_EQ(l.server->received(), 0u);
    }
    {
        Listener l({}, [](dicom::StorageServer& s) { s.requireHost("MODALITY1", "localhost"); });
        EXPECT_EQ(l.store("MODALITY1", files), "");
        EXPECT_EQ(l.server->received(), files.size());
    }
    EXPECT_THROW(Listener({}, [](dicom::StorageServer& s) { s.requireHost("MODALITY1", "no-such-host.invalid"); }),
                 core::Error);
}

// The receiver over TLS: a modality with a certificate the trusted CA signed stores; plain
// DICOM, and TLS without a client certificate, are refused.
TEST(StorageServer, OverTlsOnlyCallersWithATrustedCertificateStore) {
    test::TempDir certs;
    test::makeTestCertificates(certs.path().string());
    const std::string d = certs.path().string() + "/";
    Listener l([&](dicom::LocalNode& n) {
        n.tlsCertificate = d + "server.crt";
        n.tlsPrivateKey = d + "server.key";
        n.tlsTrustedCertificate = d + "ca.crt";
    });
    test::TempDir src;
    const auto files = series(src.file("s"));
    const std::string to = " -aet MODALITY1 -aec HOLOVOX 127.0.0.1 " + std::to_string(l.local.port) + " ";
    std::string all;
    for (const auto& f : files) all += " " + f;
    auto r = test::runCommand("storescu +tls " + d + "client.key " + d + "client.crt +cf " + d + "ca.crt" + to + all + " 2>&1");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(l.server->received(), files.size());
    r = test::runCommand("storescu" + to + files[0] + " 2>&1");
    EXPECT_NE(r.exitCode, 0) << "plain DICOM to the TLS port: " << r.output;
    r = test::runCommand("storescu +tla +cf " + d + "ca.crt" + to + files[0] + " 2>&1");
    EXPECT_NE(r.exitCode, 0) << "TLS without a client certificate: " << r.output;
    EXPECT_EQ(l.server->received(), files.size());
    EXPECT_FALSE(l.echoes()) << "echoscu without TLS must not be answered";
}

TEST(StorageServer, HostileUidsNeverEscapeTheStorageFolder) {
    Listener l;
    test::TempDir src;
    dicom::DicomWriteOptions o;
    o.studyUid = "../../../../tmp/evil";
    o.seriesUid = "..";
    const auto files = series(src.file("s"), o);
    l.store("MODALITY1", files);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    std::lock_guard lock(l.mutex);
    ASSERT_EQ(l.got.size(), 4u);
    for (const auto& in : l.got) {
        const auto rel = std::filesystem::relative(in.path, l.local.storageDir);
        for (const auto& part : rel) EXPECT_NE(part.string(), "..") << rel;
        EXPECT_EQ(std::filesystem::weakly_canonical(in.path).string().rfind(l.local.storageDir, 0), 0u) << in.path;
    }
    EXPECT_FALSE(std::filesystem::exists("/tmp/evil"));
}

TEST(StorageServer, GarbageAndOversizedPdusDoNotHurtIt) {
    Listener l;
    std::mt19937 rng(1);
    std::string garbage(4096, '\0');
    for (auto& c : garbage) c = char(rng());
    sendRaw(l.local.port, garbage);
    // An A-ASSOCIATE-RQ PDU header that claims 2 GB of payload.
    sendRaw(l.local.port, std::string("\x01\x00\x7f\xff\xff\xff", 6) + std::string(1000, 'A'));
    // A P-DATA PDU without any association.
    sendRaw(l.local.port, std::string("\x04\x00\x00\x00\x00\x10", 6) + std::string(16, '\x01'));
    test::TempDir src;
    EXPECT_EQ(l.store("MODALITY1", series(src.file("s"))), "");
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    EXPECT_EQ(l.server->received(), 4u);
    EXPECT_EQ(filesUnder(l.local.storageDir), 4u);
}

TEST(StorageServer, PortInUseIsAClearError) {
    Listener l;
    dicom::StorageServer second(l.local, {}, {});
    try {
        second.start();
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot listen on port " + std::to_string(l.local.port)), std::string::npos)
            << e.what();
    }
}

namespace {
/// A connection that sends the first 6 bytes of an A-ASSOCIATE-RQ and then nothing.
int halfOpen(std::uint16_t port) {
    const int s = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(port);
    if (::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return -1;
    ::send(s, "\x01\x00\x00\x00\x00\xcd", 6, MSG_NOSIGNAL);
    return s;
}

std::string tail(const std::string& path, std::size_t n) {
    std::ifstream in(path, std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return all.size() > n ? all.substr(all.size() - n) : all;
}
}  // namespace

// A half-open association held while three senders store 100 instances each: every instance
// arrives, with its pixels, well within the time a blocked receiver would need.
TEST(StorageServer, HalfOpenPeerDoesNotBlockThreeSenders) {
    Listener l;
    test::TempDir src;
    std::vector<std::vector<std::string>> files(3);
    for (int s = 0; s < 3; ++s) {
        core::PhantomVoxelSource p({16, 16, 100}, std::uint64_t(s + 1));
        dicom::DicomWriteOptions o;
        o.patientName = "SENDER^" + std::to_string(s);
        core::JobContext job;
        files[std::size_t(s)] = dicom::DicomSeriesWriter::write(p, src.file("s" + std::to_string(s)), o, job);
    }
    const int blocker = halfOpen(l.local.port);
    ASSERT_GE(blocker, 0);
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> errors(3);
    std::vector<std::thread> senders;
    for (int s = 0; s < 3; ++s) senders.emplace_back([&, s] { errors[std::size_t(s)] = l.store("MODALITY1", files[std::size_t(s)]); });
    for (auto& t : senders) t.join();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ::close(blocker);
    for (const auto& e : errors) EXPECT_EQ(e, "");
    EXPECT_LT(seconds, 30.0);
    std::printf("300 instances from 3 senders beside a half-open peer: %.1f s\n", seconds);
    EXPECT_EQ(l.server->received(), 300u);
    // Each stored file holds its source's pixels (the data set's last 512 bytes).
    std::size_t same = 0;
    for (const auto& series : files)
        for (const auto& f : series) {
            dicom::DicomInstance in;
            ASSERT_EQ(dicom::DicomHeaderReader::read(f, in), dicom::DicomHeaderReader::Kind::Dicom);
            std::lock_guard lock(l.mutex);
            for (const auto& got : l.got)
                if (got.sopInstanceUid == in.sopInstanceUid) same += tail(got.path, 512) == tail(f, 512);
        }
    EXPECT_EQ(same, 300u);
}

// Each connection's A-ASSOCIATE-RQ is read on its own worker: five half-open peers do not delay
// an association that follows them (read on the listening thread, as DCMTK's own accept loop
// does, they would hold every later caller for the socket read timeout, 10 s each).
TEST(StorageServer, HalfOpenPeersDoNotDelayTheNextAssociation) {
    Listener l;
    std::vector<int> blockers;
    for (int i = 0; i < 5; ++i) {
        blockers.push_back(halfOpen(l.local.port));
        ASSERT_GE(blockers.back(), 0);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const auto start = std::chrono::steady_clock::now();
    const bool echoed = l.echoes();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (int b : blockers) ::close(b);
    EXPECT_TRUE(echoed);
    EXPECT_LT(seconds, 2.0) << "an echo waited behind half-open peers";
    std::printf("C-ECHO beside 5 half-open peers: %.2f s\n", seconds);
}

// A flood of connections that send nothing costs a bounded number of workers: the ones beyond
// it are closed at once, and once the flood has gone the receiver answers again.
TEST(StorageServer, ConnectionFloodIsBoundedAndPasses) {
    Listener l;
    std::vector<int> flood;
    for (int i = 0; i < 4 * dicom::StorageServer::kMaxAssociations; ++i) flood.push_back(halfOpen(l.local.port));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    // Connections past twice the association limit were closed by the receiver: reading them
    // ends (0 bytes, or a reset, as they had sent bytes it never read) instead of waiting.
    std::size_t closedByReceiver = 0;
    for (int s : flood) {
        if (s < 0) continue;
        timeval tv{0, 50000};
        ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        char c;
        const auto n = ::recv(s, &c, 1, 0);
        closedByReceiver += n == 0 || (n < 0 && errno == ECONNRESET);
    }
    EXPECT_GE(closedByReceiver, std::size_t(2 * dicom::StorageServer::kMaxAssociations) - 2);
    for (int s : flood) ::close(s);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_TRUE(l.echoes());
}

// The receiver listens on the configured address only: 127.0.0.2 answers, 127.0.0.1 is refused.
TEST(StorageServer, ListensOnTheBindAddressOnly) {
    Listener l([](dicom::LocalNode& n) { n.bindAddress = "127.0.0.2"; });
    const std::string port = std::to_string(l.local.port);
    EXPECT_EQ(test::runCommand("echoscu -aet MODALITY1 -aec HOLOVOX 127.0.0.2 " + port + " 2>&1").exitCode, 0);
    const auto refused = test::runCommand("echoscu -to 3 -aet MODALITY1 -aec HOLOVOX 127.0.0.1 " + port + " 2>&1");
    EXPECT_NE(refused.exitCode, 0);
    EXPECT_NE(refused.output.find("refused"), std::string::npos) << refused.output;
    // An address that is not this machine's is refused with a sentence naming it.
    dicom::LocalNode other = l.local;
    other.bindAddress = "192.0.2.1";  // TEST-NET-1: never a local address
    dicom::StorageServer elsewhere(other, {"MODALITY1"}, {});
    try {
        elsewhere.start();
        FAIL() << "listened on an address that is not this machine's";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("192.0.2.1"), std::string::npos) << e.what();
    }
}

// stop() returns within about a second while one peer is half-open and another sender is
// frozen in the middle of its association.
TEST(StorageServer, StopReturnsWithinASecondWhilePeersStall) {
    auto l = std::make_unique<Listener>();
    test::TempDir src;
    core::PhantomVoxelSource p({512, 512, 40}, 3);
    core::JobContext job;
    const auto files = dicom::DicomSeriesWriter::write(p, src.file("big"), {}, job);
    std::string cmd = "storescu -aet MODALITY1 -aec HOLOVOX 127.0.0.1 " + std::to_string(l->local.port);
    for (const auto& f : files) cmd += " " + f;
    FILE* sender = ::popen((cmd + " >/dev/null 2>&1 & echo $!").c_str(), "r");
    ASSERT_NE(sender, nullptr);
    int pid = 0;
    ASSERT_EQ(std::fscanf(sender, "%d", &pid), 1);
    ::pclose(sender);
    for (int i = 0; i < 100 && l->server->received() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_GT(l->server->received(), 0u) << "the sender never got going";
    ::kill(pid, SIGSTOP);  // frozen mid-association
    const int blocker = halfOpen(l->local.port);  // and the listener reading a request that never comes
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const auto start = std::chrono::steady_clock::now();
    l->server->stop();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ::kill(pid, SIGKILL);
    ::close(blocker);
    EXPECT_LT(seconds, 1.5) << "stop() waited for a stalled peer";
    EXPECT_LT(l->server->received(), files.size());
    std::size_t partial = 0;
    for (const auto& f : std::filesystem::recursive_directory_iterator(l->local.storageDir))
        partial += f.path().extension() == ".part";
    EXPECT_EQ(partial, 0u) << "a half-received instance was left behind";
}

TEST(Dcmqrscp, EchoFindAndGetAgainstDcmtksServer) {
    test::PacsPeer peer(test::PacsPeer::Kind::Dcmqrscp);
    peer.start();
    test::TempDir src;
    dicom::DicomWriteOptions o;
    o.patientName = "QR^TEST";
    o.studyUid = "1.2.826.0.1.3680043.9.7777.40";
    o.seriesUid = "1.2.826.0.1.3680043.9.7777.41";
    const auto files = series(src.file("s"), o);
    peer.seed(files);
    auto s = peer.settings();
    dicom::PacsClient client(s.local, s.nodes[0]);
    EXPECT_NO_THROW(client.echo());
    std::vector<dicom::QueryResult> found;
    client.find(dicom::QueryLevel::Study, {"QR*", "", "", "", "", "", "", ""}, [&](const dicom::QueryResult& r) {
        found.push_back(r);
        return true;
    });
    ASSERT_EQ(found.size(), 1u);
    EXPECT_EQ(found[0].studyUid, o.studyUid);
    test::TempDir out;
    std::size_t stored = 0;
    const auto p = client.get(o.studyUid, o.seriesUid, out.file("rx"), [&](const dicom::DicomInstance&) { ++stored; }, {});
    EXPECT_EQ(stored, 4u);
    EXPECT_EQ(p.failed, 0);
    // dcmqrscp refuses an unknown move destination with 0xA801.
    try {
        client.move(o.studyUid, "", "NOBODY", {});
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("move destination 'NOBODY' is unknown"), std::string::npos) << e.what();
    }
    // And C-MOVE to a registered destination (our storage SCP) works.
    test::TempDir rx;
    s.local.storageDir = rx.file("rx");
    std::atomic<int> moved{0};
    dicom::StorageServer server(s.local, {peer.aeTitle()}, [&](const dicom::DicomInstance&) { ++moved; });
    server.start();
    const auto m = client.move(o.studyUid, "", "HOLOVOX", {});
    EXPECT_EQ(m.completed, 4);
    server.stop();
    EXPECT_EQ(moved.load(), 4);
}
