#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "core/image/RenderImage.h"

namespace hvx::core {

/// Adaptive frame reconstruction (thesis §3.3, Figs 3.11–3.12): while the view moves, each
/// frame draws one of four quincunx sub-frames (a quarter of the pixels, RenderSettings::
/// subFrame) and the full image is rebuilt from it and the frames before. A missing pixel Q
/// blends its own last value towards a spatial estimate from its four neighbours (the mean of
/// the opposite pair that differ least), by smoothstep(ΔQ, Δl, Δh) of ΔQ, how much its freshly
/// drawn neighbours changed since they were drawn before (the thesis compares them with the
/// last frame shown, rebuilt values included; comparing drawn with drawn sees only the scene's
/// own change): sharp where the image stands still, recent (if blurred) where it moves. The
/// diagonal neighbours of the fresh pixels are rebuilt first, then the horizontal and vertical
/// ones from them. A pixel whose sub-frame was drawn for the same view keeps its drawn value,
/// so once the four sub-frames of one view are in, the image is that view's full frame exactly.
///
/// Threading: one owner.
class FrameReconstructor {
public:
    static constexpr int kSubFrames = 4;
    /// The pixels (x mod 2, y mod 2) of sub-frame k: (0, 0), (1, 1), (1, 0), (0, 1); the first
    /// two together make a quincunx lattice.
    static glm::ivec2 phase(int k);

    /// Δl and Δh: colour changes (the largest of r, g, b, a, premultiplied, in [0, 1]) below
    /// which a pixel keeps its last value and above which it takes the spatial estimate.
    explicit FrameReconstructor(float low = 0.02f, float high = 0.12f) : low_(low), high_(high) {}

    /// The sub-frame to draw next (0, 1, 2, 3, 0, …).
    int next() const { return next_; }
    /// Takes sub-frame k of the view numbered `view` (equal numbers: the same camera), an image
    /// of the full size of which only sub-frame k's pixels are read; returns the rebuilt frame
    /// (valid until the next call). A size other than the last one's starts afresh.
    const RenderImage& add(const RenderImage& subFrame, int k, std::uint64_t view);
    /// Forgets every earlier frame.
    void reset();

private:
    void rebuild(int k, std::uint64_t view);

    float low_, high_;
    int next_ = 0;
    RenderImage latest_;  // each pixel's value when it was last drawn
    std::vector<glm::vec4> previous_;  // the fresh pixels' values before they were drawn again
    std::vector<glm::vec4> shown_;     // the frame returned last
    RenderImage out_;
    bool hadPrevious_ = false;
    std::array<std::uint64_t, kSubFrames> views_{};
    std::array<bool, kSubFrames> have_{};
    bool haveShown_ = false;
};

}  // namespace hvx::core
