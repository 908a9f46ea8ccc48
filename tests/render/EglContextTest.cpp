#include <gtest/gtest.h>

#include "render/EglOffscreenContext.h"

TEST(EglOffscreenContext, HeadlessGl45CoreContextOnMesa) {
    hvx::render::EglOffscreenContext ctx;
    const auto info = ctx.info();
    EXPECT_GE(info.major * 10 + info.minor, 45) << info.version;
    EXPECT_FALSE(info.renderer.empty());
    std::printf("GL renderer: %s (%s)\n", info.renderer.c_str(), info.version.c_str());
}
