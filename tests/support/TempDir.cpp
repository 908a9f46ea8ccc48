#include "tests/support/TempDir.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace hvx::test {

TempDir::TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "hvx-test-XXXXXX").string();
    if (!::mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

std::vector<std::string> TempDir::entries() const {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(path_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace hvx::test
