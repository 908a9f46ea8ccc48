#include "core/octree/Brick.h"

namespace hvx::core {

double Brick::value(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    const std::size_t i = (std::size_t(z) * edge + y) * edge + x;
    if (lossy8) return quantMin + double(as<std::uint8_t>()[i]) * (double(quantMax) - quantMin) / 255.0;
    return dispatchScalar(type, [&](auto tag) { return double(as<decltype(tag)>()[i]); });
}

SplitVoxel Brick::cell(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    const std::size_t bytes = SplitVoxel::encodedSize(scalarSize(type));
    const std::size_t i = (std::size_t(z) * edge + y) * edge + x;
    return SplitVoxel::decode(reinterpret_cast<const std::uint8_t*>(data.data()) + i * bytes, scalarSize(type),
                              type == ScalarType::Int16);
}

}  // namespace hvx::core
