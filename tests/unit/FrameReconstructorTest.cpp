// Adaptive frame reconstruction (thesis §3.3) on images drawn here: four sub-frames of a still
// view give its full frame exactly; a moving image is rebuilt closer to its full frames than
// the same quarter of the rays drawn at half resolution; where part of the image stands still
// it stays sharp; bad input is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/base/Error.h"
#include "core/image/FrameReconstructor.h"

using namespace hvx;

namespace {
// A still background (rings) and a disk at (cx, cy): colours in [0, 1], premultiplied-alike.
core::RenderImage scene(int w, int h, double cx, double cy) {
    core::RenderImage img;
    img.width = w;
    img.height = h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double r = std::hypot(x - w * 0.3, y - h * 0.6);
            const float ring = float(0.5 + 0.5 * std::cos(r * 0.35));
            glm::vec4 c(0.6f * ring, 0.3f * ring, 0.2f, 1.0f);
            const double d = std::hypot(x - cx, y - cy);
            if (d < 14) c = glm::vec4(0.9f, 0.85f, 0.8f * float(0.5 + 0.5 * std::sin(x * 0.7)), 1.0f);
            img.rgba.push_back(c);
            img.depth.push_back(float(d));
        }
    return img;
}

double psnr(const core::RenderImage& a, const core::RenderImage& b, int x0 = 0, int x1 = 1 << 30) {
    double sum = 0;
    std::size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = std::max(0, x0); x < std::min(a.width, x1); ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(a.width) + std::size_t(x);
            for (int c = 0; c < 4; ++c) sum += double(a.rgba[i][c] - b.rgba[i][c]) * double(a.rgba[i][c] - b.rgba[i][c]);
            n += 4;
        }
    return sum == 0 ? 1e9 : 10 * std::log10(double(n) / sum);
}

// The same quarter of the rays as a sub-frame, drawn at half resolution and shown enlarged
// (nearest pixel, as a reduced-resolution frame is).
core::RenderImage halfResolution(const core::RenderImage& full) {
    core::RenderImage out = full;
    for (int y = 0; y < full.height; ++y)
        for (int x = 0; x < full.width; ++x)
            out.rgba[std::size_t(y) * std::size_t(full.width) + std::size_t(x)] =
                full.rgba[std::size_t(y & ~1) * std::size_t(full.width) + std::size_t(x & ~1)];
    return out;
}
}  // namespace

TEST(FrameReconstructor, FourSubFramesOfAStillViewAreItsFullFrameExactly) {
    const auto full = scene(97, 64, 50, 30);  // an odd width: the last column has no right neighbour
    core::FrameReconstructor r;
    for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(r.next(), k);
        const auto& out = r.add(full, k, 7);
        std::printf("after sub-frame %d: %.1f dB from the full frame\n", k, psnr(out, full));
        if (k < 3) EXPECT_LT(psnr(out, full), 200.0) << "not yet all of it";
        else EXPECT_EQ(out.rgba, full.rgba) << "the quincunx cycle gives the full frame";
        if (k == 1) EXPECT_GT(psnr(out, full), 25.0) << "half the pixels, as a quincunx, already give most of it";
    }
    EXPECT_EQ(r.next(), 0);
    EXPECT_EQ(r.add(full, 0, 7).rgba, full.rgba) << "and stays it";
    // A sub-frame of another view: no longer whole until that view's four are in.
    const auto moved = scene(97, 64, 54, 30);
    for (int k = 1; k < 5; ++k) {
        const auto& out = r.add(moved, k % 4, 8);
        if (k < 4) EXPECT_NE(out.rgba, moved.rgba);
        else EXPECT_EQ(out.rgba, moved.rgba);
    }
}

TEST(FrameReconstructor, AMovingImageIsRebuiltBetterThanAtHalfResolutionAndItsStillPartStaysSharp) {
    core::FrameReconstructor r;
    double rebuilt = 0, half = 0, still = 1e9;
    int frames = 0;
    for (int f = 0; f < 40; ++f) {
        const auto full = scene(128, 96, 70 + 1.5 * f, 40 + 0.5 * f);  // a disk moving over still rings
        const auto& out = r.add(full, r.next(), std::uint64_t(f));
        if (f < 8) continue;  // let it fill
        rebuilt += psnr(out, full);
        half += psnr(halfResolution(full), full);
        still = std::min(still, psnr(out, full, 0, 40));  // columns the disk never reaches
        ++frames;
    }
    rebuilt /= frames;
    half /= frames;
    std::printf("moving: rebuilt %.1f dB, half resolution %.1f dB; the still part at worst %.1f dB\n", rebuilt, half, still);
    EXPECT_GT(rebuilt, half + 3.0);
    EXPECT_GT(still, 60.0) << "where nothing moves, older samples keep the image sharp";
}

TEST(FrameReconstructor, BadInputIsRefused) {
    EXPECT_THROW(core::FrameReconstructor::phase(4), core::Error);
    EXPECT_THROW(core::FrameReconstructor::phase(-1), core::Error);
    core::FrameReconstructor r;
    auto img = scene(16, 16, 8, 8);
    img.rgba.pop_back();
    EXPECT_THROW(r.add(img, 0, 1), core::Error);
    EXPECT_THROW(r.add(scene(16, 16, 8, 8), 5, 1), core::Error);
    // A new size starts afresh rather than mixing two sizes.
    r.add(scene(16, 16, 8, 8), 0, 1);
    const auto& out = r.add(scene(20, 10, 8, 8), 1, 1);
    EXPECT_EQ(out.width, 20);
    EXPECT_EQ(out.rgba.size(), 200u);
}
