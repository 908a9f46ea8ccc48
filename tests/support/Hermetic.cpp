// Compiled into every test executable: before any test runs, HOME and the XDG folders point
// into a fresh temporary folder (and Holovox's own path variables are cleared), so nothing a
// test does, nor any holovox-cli it starts, touches the user's settings or data. When the
// process ends, every process still running from that folder (a demo archive's Orthanc, say)
// is stopped and the folder removed.
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <exception>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace {

std::vector<pid_t> processesUsing(const std::string& folder) {
    std::vector<pid_t> found;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator("/proc", ec)) {
        const std::string name = e.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        const pid_t pid = pid_t(std::stol(name));
        if (pid == ::getpid()) continue;
        // A process that exits while its cmdline is read makes the read fail (ESRCH), which
        // libstdc++'s filebuf throws through istreambuf_iterator: that process is gone anyway.
        std::string cmdline;
        try {
            std::ifstream in(e.path() / "cmdline", std::ios::binary);
            cmdline.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        } catch (const std::exception&) {
            continue;
        }
        if (cmdline.find(folder) != std::string::npos) found.push_back(pid);
    }
    return found;
}

struct Hermetic {
    std::string home;
    Hermetic() {
        char pattern[] = "/tmp/hvx-test-home-XXXXXX";
        if (!::mkdtemp(pattern)) {
            std::perror("hermetic test home");
            std::abort();
        }
        home = pattern;
        ::setenv("HOME", home.c_str(), 1);
        for (const char* dir : {"XDG_CONFIG_HOME", "XDG_DATA_HOME", "XDG_CACHE_HOME", "XDG_STATE_HOME"}) {
            const std::string path = home + "/" + dir;
            std::filesystem::create_directories(path);
            ::setenv(dir, path.c_str(), 1);
        }
        ::unsetenv("HOLOVOX_DB");
        ::unsetenv("HOLOVOX_PACS_CONFIG");
    }
    ~Hermetic() {
        auto left = processesUsing(home);
        for (pid_t p : left) ::kill(p, SIGTERM);
        for (int i = 0; i < 50 && !left.empty(); ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            left = processesUsing(home);
        }
        for (pid_t p : left) ::kill(p, SIGKILL);
        std::error_code ec;
        std::filesystem::remove_all(home, ec);
    }
};

const Hermetic hermetic;

}  // namespace
