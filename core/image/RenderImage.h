#pragma once
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

namespace hvx::core {

/// A rendered frame: premultiplied RGBA (linear floats), depth (world mm along the ray to the
/// first significant sample, +inf when none) and, on request, rays per index node.
struct RenderImage {
    int width = 0, height = 0;
    std::vector<glm::vec4> rgba;
    std::vector<float> depth;
    std::vector<std::uint32_t> rayCounts;
    std::vector<std::uint32_t> overlayRayCounts;  ///< a fused second volume's, per its index node
};

}  // namespace hvx::core
