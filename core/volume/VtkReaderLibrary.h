#pragma once

#include "core/volume/VtkReaderAbi.h"

namespace hvx::core {

/// The VTK reader module (libhvx_vtk_reader.so, VtkReaderAbi.h), loaded once, on first use,
/// from the executable's run path: lib/holovox in the build tree, ../lib/.../holovox beside an
/// installed executable. Loading VTK only for the files that need it keeps its libraries out of
/// every start of the CLI and the workstation (8.5 ms of holovox-cli's 23.5 ms here).
///
/// Threading: api() may be called from any thread; the first call loads the module.
class VtkReaderLibrary {
public:
    /// The module's functions; throws core::Error saying why the module cannot be loaded.
    static const HvxVtkReaderApi& api();
    /// The module's file name, as looked up on the run path.
    static constexpr const char* kFileName = "libhvx_vtk_reader.so";
};

}  // namespace hvx::core
