#include "core/image/LightFieldSimulator.h"

#include <cmath>

#include <glm/trigonometric.hpp>

#include "core/base/Error.h"

namespace hvx::core {

RenderImage LightFieldSimulator::observe(const DisplayModel& display, const std::vector<RenderImage>& images,
                                         const glm::dvec3& observer) {
    if (display.kind != DisplayModel::Kind::ProjectorArray) throw Error("the simulator needs a projector-array display");
    if (int(images.size()) != display.projectors)
        throw Error("the simulator needs " + std::to_string(display.projectors) + " projector images, not " +
                    std::to_string(images.size()));
    const int w = images.front().width, h = images.front().height;
    for (const auto& im : images)
        if (im.width != w || im.height != h) throw Error("projector images differ in size");
    if (!(observer.z > 0)) throw Error("the observer must stand in front of the screen (z > 0)");
    RenderImage out;
    out.width = w;
    out.height = h;
    out.rgba.assign(std::size_t(w) * std::size_t(h), glm::vec4(0.0f));
    out.depth.assign(out.rgba.size(), INFINITY);
    const double phi = glm::radians(display.beamAngleDegrees);
    std::vector<glm::dvec3> E;
    for (int i = 0; i < display.projectors; ++i) E.push_back(display.projectorPosition(i));
    for (int x = 0; x < w; ++x) {
        const double sx = ((x + 0.5) / w - 0.5) * display.screenWidthMm;
        const double toObserver = std::atan2(observer.x - sx, observer.z);
        int best = -1;
        double bestDiff = 1e300;
        for (int i = 0; i < display.projectors; ++i) {
            const double beam = std::atan2(sx - E[std::size_t(i)].x, -E[std::size_t(i)].z);  // leaves the screen at this angle
            const double diff = std::abs(beam - toObserver);
            if (diff < bestDiff) bestDiff = diff, best = i;
        }
        if (best < 0 || bestDiff > phi) continue;  // outside the display's field of view
        const auto& src = images[std::size_t(best)];
        for (int y = 0; y < h; ++y) {
            const std::size_t k = std::size_t(y) * std::size_t(w) + std::size_t(x);
            out.rgba[k] = src.rgba[k];
            out.depth[k] = src.depth[k];
        }
    }
    return out;
}

}  // namespace hvx::core
