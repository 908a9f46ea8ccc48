#pragma once
#include <limits>

#include "core/base/ThreadPool.h"
#include "core/camera/View.h"
#include "core/image/RenderImage.h"

namespace hvx::core {

/// An image of `view`'s size with each pixel's colour and depth from `cast(origin, direction,
/// depth&)` for the pixel's ray; rows spread over ThreadPool::shared(). The casters without ray
/// counts share it.
template <class Cast>
RenderImage castPixelRays(const View& view, Cast&& cast) {
    RenderImage img;
    img.width = view.width;
    img.height = view.height;
    img.rgba.assign(std::size_t(view.width) * std::size_t(view.height), glm::vec4(0.0f));
    img.depth.assign(img.rgba.size(), std::numeric_limits<float>::infinity());
    ThreadPool::shared().parallelFor(std::size_t(view.height), [&](std::size_t y0, std::size_t y1) {
        for (std::size_t y = y0; y < y1; ++y)
            for (int x = 0; x < view.width; ++x) {
                glm::dvec3 o, d;
                view.ray(x, double(y), o, d);
                const std::size_t i = y * std::size_t(view.width) + std::size_t(x);
                img.rgba[i] = cast(o, d, img.depth[i]);
            }
    }, 8);
    return img;
}

}  // namespace hvx::core
