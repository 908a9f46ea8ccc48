#include <cstdio>

#include "app/cli/Commands.h"
#include "dicom/LibraryVersions.h"

namespace hvx::app {

int versionCommand(int, char**) {
    std::printf("holovox-cli %s\n", HVX_VERSION);
    for (const auto& [name, version] : dicom::LibraryVersions::all()) std::printf("  %-9s %s\n", name.c_str(), version.c_str());
    return 0;
}

}  // namespace hvx::app
