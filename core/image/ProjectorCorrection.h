#pragma once
#include <array>
#include <string>
#include <vector>

#include "core/image/RenderImage.h"

namespace hvx::core {

/// The optional correction pass of multi-projector displays: per projector, a geometric warp
/// (a grid of pixel offsets, interpolated bilinearly: output pixel p shows the input at p + offset)
/// and a colour correction (a 256-entry lookup table per channel, applied to linear values).
/// Loaded from JSON: {"projectors": [{"grid": [W, H], "offsets": [[dx, dy], ...] (W*H, row by
/// row), "lut": {"r": [...], "g": [...], "b": [...]}}, ...]}; a projector without an entry is
/// left as it is, and one entry alone applies to every projector.
///
/// Threading: immutable after load; apply() from any thread.
class ProjectorCorrection {
public:
    /// Throws core::Error naming the file and what is wrong.
    static ProjectorCorrection load(const std::string& path);
    static ProjectorCorrection parse(const std::string& json, const std::string& what);
    /// The corrected image of projector `index`.
    RenderImage apply(const RenderImage& image, std::size_t index) const;
    std::size_t size() const { return entries_.size(); }

private:
    struct Entry {
        int gridW = 0, gridH = 0;
        std::vector<std::array<float, 2>> offsets;
        bool hasLut = false;
        std::array<std::array<float, 256>, 3> lut{};
    };
    std::vector<Entry> entries_;
};

}  // namespace hvx::core
