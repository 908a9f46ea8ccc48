#include <cstdio>

#include "app/cli/Commands.h"
#include "render/EglOffscreenContext.h"

namespace hvx::app {

int glInfoCommand(int, char**) {
    render::EglOffscreenContext ctx;
    const auto info = ctx.info();
    std::printf("OpenGL %d.%d core (EGL surfaceless)\n  vendor   %s\n  renderer %s\n  version  %s\n", info.major,
                info.minor, info.vendor.c_str(), info.renderer.c_str(), info.version.c_str());
    return 0;
}

}  // namespace hvx::app
