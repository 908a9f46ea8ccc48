#include "ui/ImageConversion.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace hvx::ui {

namespace {
const std::array<std::uint8_t, 4096>& srgbTable() {
    static const auto table = [] {
        std::array<std::uint8_t, 4096> t{};
        for (std::size_t i = 0; i < t.size(); ++i) {
            const double c = double(i) / double(t.size() - 1);
            const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
            t[i] = std::uint8_t(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
        }
        return t;
    }();
    return table;
}
}  // namespace

QImage toQImage(const core::RenderImage& img) {
    QImage out(img.width, img.height, QImage::Format_RGB32);
    const auto& lut = srgbTable();
    auto c = [&](float v) { return lut[std::size_t(std::clamp(v, 0.0f, 1.0f) * 4095.0f)]; };
    for (int y = 0; y < img.height; ++y) {
        auto* row = reinterpret_cast<QRgb*>(out.scanLine(y));
        for (int x = 0; x < img.width; ++x) {
            const auto& p = img.rgba[std::size_t(y) * std::size_t(img.width) + std::size_t(x)];
            row[x] = qRgb(c(p.r), c(p.g), c(p.b));
        }
    }
    return out;
}

}  // namespace hvx::ui
