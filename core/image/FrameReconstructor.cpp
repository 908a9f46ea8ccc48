#include "core/image/FrameReconstructor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/common.hpp>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
float difference(const glm::vec4& a, const glm::vec4& b) {
    const glm::vec4 d = glm::abs(a - b);
    return std::max(std::max(d.r, d.g), std::max(d.b, d.a));
}
float smoothstep(float lo, float hi, float x) {
    const float t = std::clamp((x - lo) / std::max(hi - lo, 1e-6f), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}
}  // namespace

glm::ivec2 FrameReconstructor::phase(int k) {
    static const glm::ivec2 phases[kSubFrames] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    if (k < 0 || k >= kSubFrames) throw Error("no quincunx sub-frame " + std::to_string(k) + " (0 to 3)");
    return phases[k];
}

void FrameReconstructor::reset() {
    next_ = 0;
    latest_ = out_ = RenderImage{};
    previous_.clear();
    shown_.clear();
    have_ = {};
    haveShown_ = hadPrevious_ = false;
}

const RenderImage& FrameReconstructor::add(const RenderImage& subFrame, int k, std::uint64_t view) {
    const glm::ivec2 ph = phase(k);
    if (subFrame.rgba.size() != std::size_t(subFrame.width) * std::size_t(subFrame.height) ||
        subFrame.depth.size() != subFrame.rgba.size())
        throw Error("a sub-frame's pixels do not match its size");
    if (subFrame.width != latest_.width || subFrame.height != latest_.height) {
        reset();
        latest_.width = subFrame.width;
        latest_.height = subFrame.height;
        latest_.rgba.assign(subFrame.rgba.size(), glm::vec4(0.0f));
        latest_.depth.assign(subFrame.rgba.size(), std::numeric_limits<float>::infinity());
        previous_.assign(subFrame.rgba.size(), glm::vec4(0.0f));
    }
    const int w = subFrame.width, h = subFrame.height;
    for (int y = ph.y; y < h; y += 2)
        for (int x = ph.x; x < w; x += 2) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            previous_[i] = latest_.rgba[i];
            latest_.rgba[i] = subFrame.rgba[i];
            latest_.depth[i] = subFrame.depth[i];
        }
    hadPrevious_ = have_[std::size_t(k)];
    views_[std::size_t(k)] = view;
    have_[std::size_t(k)] = true;
    next_ = (k + 1) % kSubFrames;
    rebuild(k, view);
    shown_ = out_.rgba;
    haveShown_ = true;
    return out_;
}

void FrameReconstructor::rebuild(int k, std::uint64_t view) {
    const int w = latest_.width, h = latest_.height;
    const glm::ivec2 ph = phase(k);
    out_.width = w;
    out_.height = h;
    out_.depth = latest_.depth;
    // Sub-frames already drawn for this very view hold exact pixels: they are kept as drawn.
    std::array<bool, kSubFrames> exact{};
    bool whole = true;
    for (std::size_t s = 0; s < kSubFrames; ++s) {
        exact[s] = have_[s] && views_[s] == view;
        whole = whole && exact[s];
    }
    if (whole || !haveShown_) out_.rgba = latest_.rgba;
    else out_.rgba = shown_;
    if (whole) return;
    auto at = [&](int x, int y) { return std::size_t(y) * std::size_t(w) + std::size_t(x); };
    auto subFrameOf = [](int x, int y) { return (x & 1) == (y & 1) ? (x & 1) : 2 + (y & 1); };  // phase() inverted
    for (int y = ph.y; y < h; y += 2)
        for (int x = ph.x; x < w; x += 2) out_.rgba[at(x, y)] = latest_.rgba[at(x, y)];
    // A missing pixel from neighbours a, c (one opposite pair) and b, d (the other), all up to
    // date in out_ (an edge's missing neighbour is its opposite's); `fresh` of them were drawn
    // in this sub-frame, and how much those changed since they were drawn before is ΔQ.
    auto fill = [&](int x, int y, glm::ivec2 da, glm::ivec2 db, int fresh) {
        const std::size_t i = at(x, y);
        if (exact[std::size_t(subFrameOf(x, y))]) {
            out_.rgba[i] = latest_.rgba[i];
            return;
        }
        auto inside = [&](glm::ivec2 p) { return p.x >= 0 && p.x < w && p.y >= 0 && p.y < h; };
        const glm::ivec2 p(x, y);
        glm::ivec2 n[4] = {p - da, p + da, p - db, p + db};
        for (int j = 0; j < 4; ++j)
            if (!inside(n[j])) n[j] = n[j ^ 1];
        for (const auto& q : n)
            if (!inside(q)) return;  // an image one pixel across: keep what it has
        const glm::vec4 A = out_.rgba[at(n[0].x, n[0].y)], C = out_.rgba[at(n[1].x, n[1].y)];
        const glm::vec4 B = out_.rgba[at(n[2].x, n[2].y)], D = out_.rgba[at(n[3].x, n[3].y)];
        const glm::vec4 spatial = difference(A, C) <= difference(B, D) ? 0.5f * (A + C) : 0.5f * (B + D);
        float change = 1.0f;  // never drawn before: all new
        if (hadPrevious_ && haveShown_) {
            change = 0.0f;
            for (int j = 0; j < fresh; ++j) {
                const std::size_t q = at(n[j].x, n[j].y);
                change = std::max(change, difference(latest_.rgba[q], previous_[q]));
            }
        }
        const glm::vec4 before = out_.rgba[i];
        out_.rgba[i] = before + smoothstep(low_, high_, change) * (spatial - before);
    };
    // The fresh pixels' diagonal neighbours, from the four fresh pixels around each.
    for (int y = (ph.y + 1) % 2; y < h; y += 2)
        for (int x = (ph.x + 1) % 2; x < w; x += 2) fill(x, y, {1, 1}, {1, -1}, 4);
    // Then the rest, each between two fresh pixels (along x in rows of the fresh ones, along y
    // in the others) and two rebuilt ones.
    for (int y = 0; y < h; ++y) {
        const bool freshRow = (y + ph.y) % 2 == 0;
        for (int x = freshRow ? (ph.x + 1) % 2 : ph.x; x < w; x += 2)
            if (freshRow) fill(x, y, {1, 0}, {0, 1}, 2);
            else fill(x, y, {0, 1}, {1, 0}, 2);
    }
}

}  // namespace hvx::core
