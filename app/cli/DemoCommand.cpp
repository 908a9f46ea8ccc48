#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "app/cli/OctreeBuildRunner.h"
#include "core/Error.h"
#include "core/VoxelSourceFactory.h"

namespace hvx::app {

namespace {
std::filesystem::path dataDir() {
    if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x) return std::filesystem::path(x) / "holovox";
    if (const char* h = std::getenv("HOME"); h && *h) return std::filesystem::path(h) / ".local/share/holovox";
    return std::filesystem::temp_directory_path() / "holovox";
}
}  // namespace

int demoCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"input", "o", "output"}, {});
    std::string input = "/usr/share/mricron/templates/ch2better.nii.gz";
    if (const char* env = std::getenv("HOLOVOX_DEMO_DATA"); env && *env) input = env;
    if (const auto i = args.value("input")) input = *i;
    std::filesystem::path out = dataDir() / "demo" / "ch2better.hvo";
    if (const auto o = args.value("o") ? args.value("o") : args.value("output")) out = *o;
    std::error_code ec;
    std::filesystem::create_directories(out.parent_path(), ec);
    if (ec) throw core::Error(out.parent_path().string() + ": cannot create directory (" + ec.message() + ")");
    std::printf("Holovox demo: building the out-of-core octree of the MRI template\n  %s\n", input.c_str());
    auto source = core::VoxelSourceFactory::open(input);
    OctreeBuildRunner::run(*source, out.string(), core::BuildOptions{}, true);
    return 0;
}

}  // namespace hvx::app
