#include "core/volume/VtkReaderLibrary.h"

#include <dlfcn.h>

#include <string>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
struct Loaded {
    const HvxVtkReaderApi* api = nullptr;
    std::string error;  // why not, when api is null
};

Loaded load() {
    Loaded out;
    // Never unloaded: VTK keeps static state that must outlive every reader.
    void* handle = ::dlopen(VtkReaderLibrary::kFileName, RTLD_LAZY | RTLD_LOCAL);
    if (!handle) {
        const char* why = ::dlerror();
        out.error = std::string("cannot load Holovox's VTK reader module (") + (why ? why : "unknown reason") +
                    "): this installation cannot read MetaImage or VTK files";
        return out;
    }
    auto entry = reinterpret_cast<HvxVtkReaderApiFunction>(::dlsym(handle, HVX_VTK_READER_API_SYMBOL));
    const HvxVtkReaderApi* api = entry ? entry() : nullptr;
    if (!api || api->abiVersion != kHvxVtkReaderAbiVersion) {
        out.error = std::string("Holovox's VTK reader module ") + VtkReaderLibrary::kFileName +
                    " belongs to another Holovox version: this installation cannot read MetaImage or VTK files";
        return out;
    }
    out.api = api;
    return out;
}
}  // namespace

const HvxVtkReaderApi& VtkReaderLibrary::api() {
    static const Loaded loaded = load();
    if (!loaded.api) throw Error(loaded.error);
    return *loaded.api;
}

}  // namespace hvx::core
