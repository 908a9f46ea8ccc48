#pragma once
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "dicom/StorageServer.h"
#include "tests/support/PacsPeer.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"

namespace hvx::test {

/// Holovox's storage SCP on a free port, storing under its own temporary folder, accepting
/// MODALITY1; what arrives is kept in `got`. `configure` may change the node, and `prepare` the
/// server, before it starts.
struct StorageListener {
    TempDir dir;
    dicom::LocalNode local;
    std::mutex mutex;
    std::vector<dicom::DicomInstance> got;
    std::unique_ptr<dicom::StorageServer> server;
    explicit StorageListener(const std::function<void(dicom::LocalNode&)>& configure = {},
                             const std::function<void(dicom::StorageServer&)>& prepare = {}) {
        local.port = freePort();
        local.storageDir = dir.file("rx");
        local.timeoutSeconds = 5;
        if (configure) configure(local);
        server = std::make_unique<dicom::StorageServer>(local, std::vector<std::string>{"MODALITY1"},
                                                        [this](const dicom::DicomInstance& in) {
                                                            std::lock_guard lock(mutex);
                                                            got.push_back(in);
                                                        });
        if (prepare) prepare(*server);
        server->start();
    }
    /// Sends the files with DCMTK's storescu in one association; "" when it succeeded, else
    /// its output.
    std::string store(const std::string& callingAe, const std::vector<std::string>& files) {
        const auto r = storeVerbose(callingAe, files);
        return r.exitCode == 0 ? "" : r.output;
    }
    /// Sends every file with storescu -v --no-halt: its exit status and what it says of each
    /// response.
    ProcessResult storeVerbose(const std::string& callingAe, const std::vector<std::string>& files) {
        std::string cmd = "storescu -v -nh -aet " + callingAe + " -aec HOLOVOX 127.0.0.1 " + std::to_string(local.port);
        for (const auto& f : files) cmd += " " + f;
        return runCommand(cmd + " 2>&1");
    }
    /// True when DCMTK's echoscu gets an answer.
    bool echoes() {
        return runCommand("echoscu -aet MODALITY1 -aec HOLOVOX 127.0.0.1 " + std::to_string(local.port) + " 2>&1")
                   .exitCode == 0;
    }
};

}  // namespace hvx::test
