#include <cstdio>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "core/base/Error.h"
#include "dicom/DicomFileProbe.h"

namespace hvx::app {

int dicomInfoCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {}, {});
    if (args.positional().empty()) throw core::Error("usage: holovox-cli dicom-info FILE...");
    int failures = 0;
    for (const auto& path : args.positional()) {
        try {
            std::printf("%s\n", dicom::DicomFileProbe::probe(path).summary().c_str());
        } catch (const core::Error& e) {
            std::fprintf(stderr, "holovox-cli: error: %s\n", e.what());
            ++failures;
        }
    }
    return failures ? 1 : 0;
}

}  // namespace hvx::app
