#include <cstdio>

#include "app/cli/Commands.h"
#include "dicom/DicomFileProbe.h"

namespace hvx::app {

int versionCommand(int, char**) {
    std::printf("holovox-cli %s\n  DCMTK %s\n", HVX_VERSION, dicom::DicomFileProbe::dcmtkVersion().c_str());
    return 0;
}

}  // namespace hvx::app
