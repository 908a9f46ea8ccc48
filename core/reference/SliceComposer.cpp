#include "core/reference/SliceComposer.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
void checkSize(const SliceImage& base, const SliceImage* layer, const char* what) {
    if (layer && (layer->width != base.width || layer->height != base.height))
        throw Error(std::string("the ") + what + " slice is " + std::to_string(layer->width) + "x" +
                    std::to_string(layer->height) + ", the base " + std::to_string(base.width) + "x" +
                    std::to_string(base.height) + ": they must be sampled on the same plane");
}

std::uint8_t blend(std::uint8_t under, std::uint8_t over, double alpha) {
    return std::uint8_t(std::lround(under + alpha * (double(over) - under)));
}

int labelAt(const SliceImage& s, int x, int y) {
    const float v = s.values[std::size_t(y) * std::size_t(s.width) + std::size_t(x)];
    return std::isnan(v) ? 0 : int(std::lround(v));
}
}  // namespace

std::vector<std::uint8_t> SliceComposer::grey(const SliceImage& base, const VolumeGeometry& g, const DisplayWindow& w) {
    std::vector<std::uint8_t> out(base.values.size(), 0);
    const double lo = w.centre - w.width / 2;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const float v = base.values[i];
        if (std::isnan(v)) continue;  // outside the volume: black
        double t = std::clamp((v * g.rescaleSlope + g.rescaleIntercept - lo) / w.width, 0.0, 1.0);
        if (g.monochrome1) t = 1.0 - t;
        out[i] = std::uint8_t(std::lround(t * 255.0));
    }
    return out;
}

std::vector<std::uint8_t> SliceComposer::compose(const SliceImage& base, const VolumeGeometry& g, const DisplayWindow& w,
                                                 const SliceOverlay* overlay, const SliceLabels* labels) {
    checkSize(base, overlay ? overlay->image : nullptr, "overlay");
    checkSize(base, labels ? labels->image : nullptr, "label");
    const auto grey = SliceComposer::grey(base, g, w);
    std::vector<std::uint8_t> rgb(grey.size() * 3);
    for (std::size_t i = 0; i < grey.size(); ++i) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = grey[i];
    if (overlay && overlay->image) {
        const auto& og = *overlay->geometry;
        const double lo = overlay->window.centre - overlay->window.width / 2;
        const double opacity = std::clamp(overlay->opacity, 0.0, 1.0);
        for (std::size_t i = 0; i < grey.size(); ++i) {
            const float v = overlay->image->values[i];
            if (std::isnan(v)) continue;
            const double t = (v * og.rescaleSlope + og.rescaleIntercept - lo) / overlay->window.width;
            // The map's first entry is not drawn (as mricron does): at or near the window's low
            // end the overlay shows nothing and the anatomy stays as it is.
            if (!(t >= 0.5 / 255)) continue;
            const auto c = overlay->map.at(t);
            for (std::size_t a = 0; a < 3; ++a) rgb[3 * i + a] = blend(rgb[3 * i + a], c[a], opacity);
        }
    }
    if (labels && labels->image && labels->table) {
        const auto& s = *labels->image;
        const double opacity = std::clamp(labels->opacity, 0.0, 1.0);
        for (int y = 0; y < s.height; ++y)
            for (int x = 0; x < s.width; ++x) {
                const int l = labelAt(s, x, y);
                const auto* e = labels->table->find(l);
                if (!e || !e->visible) continue;
                // A border pixel: a 4-neighbour inside the image holds another label.
                bool border = false;
                if (labels->outline)
                    for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                        const int nx = x + dx, ny = y + dy;
                        if (nx >= 0 && ny >= 0 && nx < s.width && ny < s.height && labelAt(s, nx, ny) != l) border = true;
                    }
                const double alpha = e->rgba[3] / 255.0 * (border ? 1.0 : labels->fill ? opacity : 0.0);
                if (alpha <= 0) continue;
                const std::size_t i = std::size_t(y) * std::size_t(s.width) + std::size_t(x);
                for (std::size_t a = 0; a < 3; ++a) rgb[3 * i + a] = blend(rgb[3 * i + a], e->rgba[a], alpha);
            }
    }
    return rgb;
}

std::vector<int> SliceComposer::labelsIn(const SliceImage& labels) {
    std::set<int> seen;
    for (const float v : labels.values)
        if (!std::isnan(v) && v != 0) seen.insert(int(std::lround(v)));
    return {seen.begin(), seen.end()};
}

}  // namespace hvx::core
