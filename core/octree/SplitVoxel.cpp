#include "core/octree/SplitVoxel.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

namespace hvx::core {

namespace {
std::int8_t quantise(float v, float range) {
    return std::int8_t(std::lround(std::clamp(v / range, -1.0f, 1.0f) * 127.0f));
}

void putValue(std::uint8_t* out, float v, std::size_t bytes, bool isSigned) {
    const long q = std::lround(v);
    if (bytes == 1) {
        out[0] = isSigned ? std::uint8_t(std::int8_t(std::clamp(q, -128L, 127L))) : std::uint8_t(std::clamp(q, 0L, 255L));
        return;
    }
    const std::uint16_t u = isSigned ? std::uint16_t(std::int16_t(std::clamp(q, -32768L, 32767L)))
                                     : std::uint16_t(std::clamp(q, 0L, 65535L));
    std::memcpy(out, &u, 2);
}

float getValue(const std::uint8_t* in, std::size_t bytes, bool isSigned) {
    if (bytes == 1) return isSigned ? float(std::int8_t(in[0])) : float(in[0]);
    std::uint16_t u;
    std::memcpy(&u, in, 2);
    return isSigned ? float(std::int16_t(u)) : float(u);
}
}  // namespace

float SplitVoxel::valueAt(const glm::vec3& p) const {
    if (isUniform()) return front;
    return glm::dot(normal, p - glm::vec3(0.5f)) >= offset ? front : back;
}

float SplitVoxel::frontFraction() const {
    if (isUniform()) return 1.0f;
    int n = 0;
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x)
                n += glm::dot(normal, (glm::vec3(float(x), float(y), float(z)) + 0.5f) / 4.0f - glm::vec3(0.5f)) >= offset;
    return float(n) / 64.0f;
}

void SplitVoxel::encode(std::uint8_t* out, std::size_t valueBytes, bool isSigned) const {
    putValue(out, front, valueBytes, isSigned);
    putValue(out + valueBytes, back, valueBytes, isSigned);
    std::uint8_t* plane = out + 2 * valueBytes;
    if (isUniform() || front == back) {
        std::memset(plane, 0, 4);
        return;
    }
    plane[0] = std::uint8_t(quantise(normal.x, 1.0f));
    plane[1] = std::uint8_t(quantise(normal.y, 1.0f));
    plane[2] = std::uint8_t(quantise(normal.z, 1.0f));
    plane[3] = std::uint8_t(quantise(offset, kMaxOffset));
    // A normal so close to an axis that every other component rounds to zero still encodes one.
    if (plane[0] == 0 && plane[1] == 0 && plane[2] == 0) plane[0] = 1;
}

SplitVoxel SplitVoxel::decode(const std::uint8_t* in, std::size_t valueBytes, bool isSigned) {
    SplitVoxel v;
    v.front = getValue(in, valueBytes, isSigned);
    v.back = getValue(in + valueBytes, valueBytes, isSigned);
    const std::uint8_t* plane = in + 2 * valueBytes;
    const glm::vec3 n{float(std::int8_t(plane[0])), float(std::int8_t(plane[1])), float(std::int8_t(plane[2]))};
    if (n == glm::vec3(0.0f) || v.front == v.back) return SplitVoxel::uniform(v.front);
    v.normal = glm::normalize(n);
    v.offset = float(std::int8_t(plane[3])) / 127.0f * kMaxOffset;
    return v;
}

}  // namespace hvx::core
