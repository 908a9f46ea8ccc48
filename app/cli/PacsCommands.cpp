#include <csignal>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <thread>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "app/cli/ProgressBar.h"
#include "app/cli/SignalCancel.h"
#include "core/base/Error.h"
#include "dicom/DicomWebUrl.h"
#include "dicom/PacsClient.h"
#include "dicom/PacsSettings.h"
#include "dicom/RetrieveJob.h"
#include "dicom/StorageOwners.h"
#include "dicom/StorageServer.h"
#include "dicom/StudyDatabase.h"

namespace hvx::app {

namespace {
dicom::PacsSettings loadSettings(const CliArgs& args) {
    return dicom::PacsSettings::load(args.value("config").value_or(dicom::PacsSettings::defaultPath()));
}

std::string octreeDir(const std::string& dbPath) {
    return (std::filesystem::path(dbPath).parent_path() / "octrees").string();
}

dicom::QueryLevel parseLevel(const std::string& s) {
    if (s == "study") return dicom::QueryLevel::Study;
    if (s == "series") return dicom::QueryLevel::Series;
    if (s == "image") return dicom::QueryLevel::Image;
    throw core::Error("--level must be study, series or image");
}

int nodesCmd(const CliArgs& args) {
    const auto s = loadSettings(args);
    std::printf("local: AE %s, storage SCP port %u, storage %s\n", s.local.aeTitle.c_str(), s.local.port,
                s.local.storageDir.c_str());
    for (const auto& n : s.nodes) {
        const char* mark = n.name == s.defaultNode ? "*" : " ";
        if (n.kind == dicom::NodeKind::DicomWeb)
            std::printf("%s %-16s DICOMweb %s%s%s\n", mark, n.name.c_str(), n.baseUrl.c_str(),
                        !n.bearerToken.empty() ? "  bearer token" : !n.username.empty() ? "  basic auth" : "",
                        n.tlsVerify ? "" : "  TLS NOT VERIFIED");
        else
            std::printf("%s %-16s AE %-16s %s:%u  retrieve %s%s\n", mark, n.name.c_str(), n.aeTitle.c_str(),
                        n.host.c_str(), n.port, n.retrieve == dicom::RetrieveMethod::Move ? "C-MOVE" : "C-GET",
                        n.tls ? "  TLS" : "");
    }
    if (s.nodes.empty()) std::printf("no remote nodes: add one with 'holovox-cli pacs add NAME --ae AE --host H --port P'\n");
    return 0;
}

int addCmd(const CliArgs& args) {
    if (args.positional().size() != 2)
        throw core::Error("usage: holovox-cli pacs add NAME --ae AE --host HOST --port PORT [--move] [--default] "
                          "[--max-pdu BYTES] [--tls --tls-ca CA.pem [--tls-cert C.pem --tls-key K.pem]]\n"
                          "       holovox-cli pacs add NAME --dicomweb URL [--token T | --user U --password P] "
                          "[--insecure] [--default]");
    const std::string path = args.value("config").value_or(dicom::PacsSettings::defaultPath());
    auto s = dicom::PacsSettings::load(path);
    dicom::PacsNode n;
    n.name = args.positional()[1];
    if (args.value("parallel")) s.local.parallelAssociations = int(args.integer("parallel", 3, 1, 16));
    if (auto url = args.value("dicomweb")) {
        n.kind = dicom::NodeKind::DicomWeb;
        n.baseUrl = *url;
        dicom::DicomWebUrl::check(n.baseUrl, "--dicomweb");
        n.bearerToken = args.value("token").value_or("");
        n.username = args.value("user").value_or("");
        n.password = args.value("password").value_or("");
        n.tlsVerify = !args.flag("insecure");
        if (!n.bearerToken.empty() && !n.username.empty()) throw core::Error("give --token or --user, not both");
        s.upsert(n);
        if (args.flag("default") || s.defaultNode.empty()) s.defaultNode = n.name;
        s.save(path);
        std::printf("saved DICOMweb node '%s' to %s\n", n.name.c_str(), path.c_str());
        return 0;
    }
    n.maxPdu = std::uint32_t(args.integer("max-pdu", dicom::kDefaultMaxPdu, 4096, 131072));
    n.aeTitle = args.value("ae").value_or("");
    n.host = args.value("host").value_or("127.0.0.1");
    n.port = std::uint16_t(args.integer("port", 104, 1, 65535));
    n.retrieve = args.flag("move") ? dicom::RetrieveMethod::Move : dicom::RetrieveMethod::Get;
    n.tls = args.flag("tls");
    n.tlsTrustedCertificate = args.value("tls-ca").value_or("");
    n.tlsCertificate = args.value("tls-cert").value_or("");
    n.tlsPrivateKey = args.value("tls-key").value_or("");
    if (n.tls && n.tlsTrustedCertificate.empty()) throw core::Error("--tls needs --tls-ca FILE (the CA that signs the node)");
    if (n.aeTitle.empty() || n.aeTitle.size() > 16) throw core::Error("--ae must be 1 to 16 characters");
    s.upsert(n);
    if (args.flag("default") || s.defaultNode.empty()) s.defaultNode = n.name;
    if (auto ae = args.value("local-ae")) s.local.aeTitle = *ae;
    if (args.value("local-port")) s.local.port = std::uint16_t(args.integer("local-port", 11112, 1, 65535));
    if (auto dir = args.value("storage")) s.local.storageDir = *dir;
    s.save(path);
    std::printf("saved node '%s' to %s\n", n.name.c_str(), path.c_str());
    return 0;
}

int echoCmd(const CliArgs& args) {
    const auto s = loadSettings(args);
    const auto& node = s.node(args.positional().size() > 1 ? args.positional()[1] : "");
    dicom::PacsClient(s.local, node).echo();
    if (node.kind == dicom::NodeKind::DicomWeb) {
        std::printf("QIDO-RS search on %s (%s) answered\n", node.name.c_str(), node.baseUrl.c_str());
        return 0;
    }
    std::printf("C-ECHO to %s (AE %s at %s:%u) succeeded\n", node.name.c_str(), node.aeTitle.c_str(), node.host.c_str(),
                node.port);
    return 0;
}

int findCmd(const CliArgs& args) {
    const auto s = loadSettings(args);
    const auto& node = s.node(args.positional().size() > 1 ? args.positional()[1] : "");
    dicom::QueryKeys k;
    k.patientName = args.value("patient").value_or("");
    k.patientId = args.value("id").value_or("");
    k.studyDate = args.value("date").value_or("");
    k.modality = args.value("modality").value_or("");
    k.accessionNumber = args.value("accession").value_or("");
    k.studyDescription = args.value("description").value_or("");
    k.studyUid = args.value("study").value_or("");
    k.seriesUid = args.value("series").value_or("");
    const auto level = parseLevel(args.value("level").value_or("study"));
    const long limit = args.integer("limit", 0, 0, 1000000);
    long shown = 0;
    const auto n = dicom::PacsClient(s.local, node).find(level, k, [&](const dicom::QueryResult& r) {
        if (level == dicom::QueryLevel::Study)
            std::printf("%-24s %-12s %-8s %-8s %-28s %4d  %s\n", r.patientName.c_str(), r.patientId.c_str(),
                        r.studyDate.c_str(), r.modalitiesInStudy.c_str(), r.studyDescription.c_str(),
                        r.numberOfInstances, r.studyUid.c_str());
        else if (level == dicom::QueryLevel::Series)
            std::printf("  series %3d %-4s %-28s %4d images  %s\n", r.seriesNumber, r.modality.c_str(),
                        r.seriesDescription.c_str(), r.numberOfInstances, r.seriesUid.c_str());
        else
            std::printf("    image %4d  %s\n", r.instanceNumber, r.sopInstanceUid.c_str());
        std::fflush(stdout);
        return limit == 0 || ++shown < limit;  // false sends C-CANCEL
    });
    std::printf("%zu results%s\n", n, limit && shown >= limit ? " (cancelled after --limit)" : "");
    return 0;
}

int retrieveCmd(const CliArgs& args, dicom::RetrieveMethod method) {
    auto s = loadSettings(args);
    if (args.positional().size() < 3)
        throw core::Error("usage: holovox-cli pacs get|move NODE STUDY_UID [SERIES_UID] [--db FILE] [--no-build]");
    dicom::PacsNode node = s.node(args.positional()[1]);
    if (node.kind == dicom::NodeKind::DicomWeb && method == dicom::RetrieveMethod::Move)
        throw core::Error("'" + node.name + "' is a DICOMweb node: it retrieves by WADO-RS ('pacs get'), not C-MOVE");
    node.retrieve = method;
    if (args.value("parallel")) s.local.parallelAssociations = int(args.integer("parallel", 3, 1, 16));
    const std::string dbPath = args.value("db").value_or(dicom::StudyDatabase::defaultPath());
    dicom::StudyDatabase db(dbPath);
    ProgressBar bar(node.kind == dicom::NodeKind::DicomWeb ? "WADO-RS" : method == dicom::RetrieveMethod::Get ? "C-GET " : "C-MOVE");
    core::JobContext job(bar.observer());
    SignalCancel cancel(job);
    dicom::RetrieveJob retrieve(s, node, db, octreeDir(dbPath));
    const auto result = retrieve.run(args.positional()[2], args.positional().size() > 3 ? args.positional()[3] : "",
                                     !args.flag("no-build"), job, {});
    bar.finish();
    int failed = 0;
    for (const auto& r : result) {
        std::printf("series %s %s: %d completed, %d failed, %d warnings%s%s%s\n", r.seriesUid.c_str(),
                    r.description.c_str(), r.progress.completed, r.progress.failed, r.progress.warning,
                    r.octreePath.empty() ? "" : ", octree ", r.octreePath.c_str(),
                    r.error.empty() ? "" : (", error: " + r.error).c_str());
        failed += !r.error.empty();
    }
    return failed ? 1 : 0;
}
}  // namespace

int pacsCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2,
                       {"config", "patient", "id", "date", "modality", "accession", "description", "level", "study",
                        "series", "limit", "db", "ae", "host", "port", "local-ae", "local-port", "storage", "tls-ca",
                        "tls-cert", "tls-key", "dicomweb", "token", "user", "password", "max-pdu", "parallel"},
                       {"move", "default", "no-build", "tls", "insecure"});
    const std::string sub = args.positional().empty() ? "" : args.positional()[0];
    if (sub == "nodes") return nodesCmd(args);
    if (sub == "add") return addCmd(args);
    if (sub == "echo") return echoCmd(args);
    if (sub == "find") return findCmd(args);
    if (sub == "get") return retrieveCmd(args, dicom::RetrieveMethod::Get);
    if (sub == "move") return retrieveCmd(args, dicom::RetrieveMethod::Move);
    if (sub == "send") {
        if (args.positional().size() < 3) throw core::Error("usage: holovox-cli pacs send NODE FILE...");
        const auto s = loadSettings(args);
        const std::vector<std::string> files(args.positional().begin() + 2, args.positional().end());
        auto local = s.local;
        if (args.value("parallel")) local.parallelAssociations = int(args.integer("parallel", 3, 1, 16));
        const auto n = dicom::PacsClient(local, s.node(args.positional()[1])).store(files, {});
        std::printf("sent %zu files, %zu accepted\n", files.size(), n);
        return n == files.size() ? 0 : 1;
    }
    throw core::Error("usage: holovox-cli pacs nodes|add|echo|find|get|move|send ...");
}

namespace {
volatile std::sig_atomic_t g_stop = 0;
extern "C" void onStop(int) { g_stop = 1; }
}  // namespace

int listenCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"config", "port", "bind", "ae", "storage", "db", "allow"}, {});
    auto s = loadSettings(args);
    if (args.value("port")) s.local.port = std::uint16_t(args.integer("port", 11112, 1, 65535));
    if (auto bind = args.value("bind")) s.local.bindAddress = *bind;
    if (auto ae = args.value("ae")) s.local.aeTitle = *ae;
    if (auto dir = args.value("storage")) s.local.storageDir = *dir;
    std::vector<std::string> allowed = s.local.allowedCallers;
    for (const auto& n : s.nodes)
        if (n.kind == dicom::NodeKind::Dimse) allowed.push_back(n.aeTitle);
    if (auto a = args.value("allow")) allowed.push_back(*a);
    dicom::StudyDatabase db(args.value("db").value_or(dicom::StudyDatabase::defaultPath()));
    dicom::StorageOwners::add(s.local.storageDir, db.path());  // what it receives, this database indexes
    std::mutex mutex;
    dicom::StorageServer server(s.local, allowed, [&](const dicom::DicomInstance& in) {
        std::lock_guard lock(mutex);
        const auto stats = db.addInstances({in});
        std::printf("received %s %s -> %s\n", in.modality.c_str(), in.sopInstanceUid.c_str(), in.path.c_str());
        for (const auto& c : stats.conflicts) std::printf("  not indexed: %s\n", c.c_str());
        std::fflush(stdout);
    });
    for (const auto& n : s.nodes)
        if (n.kind == dicom::NodeKind::Dimse) server.requireHost(n.aeTitle, n.host);
    server.start();
    std::string who;
    for (const auto& a : allowed) who += (who.empty() ? "" : ", ") + a;
    std::printf("storage SCP AE %s listening on port %u of %s, storing into %s; accepting %s (Ctrl-C stops)\n",
                s.local.aeTitle.c_str(), s.local.port,
                s.local.bindAddress.empty() ? "all interfaces" : s.local.bindAddress.c_str(), s.local.storageDir.c_str(), who.empty() ? "nobody" : who.c_str());
    std::fflush(stdout);
    std::signal(SIGINT, onStop);
    std::signal(SIGTERM, onStop);
    while (!g_stop) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    server.stop();
    std::printf("stopped after %zu instances\n", server.received());
    return 0;
}

}  // namespace hvx::app
