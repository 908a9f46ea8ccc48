#pragma once
#include <cmath>

#include <glm/geometric.hpp>

#include "core/reference/CpuRayCaster.h"

namespace hvx::test {

/// PSNR (dB) of two rendered images over premultiplied RGBA clamped to [0, 1]; 99 when equal.
inline double psnr(const core::RenderImage& a, const core::RenderImage& b) {
    double se = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) {
        const glm::vec4 d = glm::clamp(a.rgba[i], 0.0f, 1.0f) - glm::clamp(b.rgba[i], 0.0f, 1.0f);
        se += double(glm::dot(d, d)) / 4.0;
    }
    const double mse = se / double(a.rgba.size());
    return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0;
}

}  // namespace hvx::test
