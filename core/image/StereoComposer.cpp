#include "core/image/StereoComposer.h"

#include <algorithm>
#include <cmath>

#include "core/base/Error.h"

namespace hvx::core {

RenderImage StereoComposer::compose(DisplayModel::StereoLayout layout, const RenderImage& l, const RenderImage& r) {
    if (l.width != r.width || l.height != r.height) throw Error("the two stereo views differ in size");
    RenderImage out;
    const bool sbs = layout == DisplayModel::StereoLayout::SideBySide;
    out.width = sbs ? 2 * l.width : l.width;
    out.height = l.height;
    out.rgba.assign(std::size_t(out.width) * std::size_t(out.height), glm::vec4(0.0f));
    out.depth.assign(out.rgba.size(), INFINITY);
    for (int y = 0; y < l.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const std::size_t o = std::size_t(y) * std::size_t(out.width) + std::size_t(x);
            if (sbs) {
                const auto& src = x < l.width ? l : r;
                const std::size_t i = std::size_t(y) * std::size_t(l.width) + std::size_t(x % l.width);
                out.rgba[o] = src.rgba[i];
                out.depth[o] = src.depth[i];
            } else if (layout == DisplayModel::StereoLayout::Anaglyph) {
                const std::size_t i = std::size_t(y) * std::size_t(l.width) + std::size_t(x);
                const float lum = 0.299f * l.rgba[i].r + 0.587f * l.rgba[i].g + 0.114f * l.rgba[i].b;
                out.rgba[o] = glm::vec4(lum, r.rgba[i].g, r.rgba[i].b, std::max(l.rgba[i].a, r.rgba[i].a));
                out.depth[o] = std::min(l.depth[i], r.depth[i]);
            } else {
                const auto& src = x % 2 == 0 ? l : r;
                const std::size_t i = std::size_t(y) * std::size_t(l.width) + std::size_t(x);
                out.rgba[o] = src.rgba[i];
                out.depth[o] = src.depth[i];
            }
        }
    return out;
}

}  // namespace hvx::core
