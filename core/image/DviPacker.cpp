#include "core/image/DviPacker.h"

#include <algorithm>
#include <cmath>

#include "core/base/Error.h"

namespace hvx::core {

std::vector<RenderImage> DviPacker::pack(const std::vector<RenderImage>& projectors) {
    std::vector<RenderImage> frames;
    for (std::size_t first = 0; first < projectors.size(); first += 16) {
        RenderImage f;
        f.width = kFrameWidth;
        f.height = kFrameHeight;
        f.rgba.assign(std::size_t(kFrameWidth) * kFrameHeight, glm::vec4(0, 0, 0, 1));
        f.depth.assign(f.rgba.size(), INFINITY);
        for (std::size_t t = 0; t < 16 && first + t < projectors.size(); ++t) {
            const auto& img = projectors[first + t];
            if (img.width != kTileWidth || img.height != kTileHeight)
                throw Error("the DVI layout needs 320x240 projector images, not " + std::to_string(img.width) + "x" +
                            std::to_string(img.height));
            const int id = int(first + t);
            // Header block: the projector id as a colour. Frames are linear and PNGs sRGB-encoded
            // (ImageWriter): the code is stored as the linear value whose 8-bit sRGB byte is the
            // id's, so the written frame carries the ids exactly (it carried 71 for 16 before).
            const glm::vec4 code(linearOfByte(id & 0xFF), linearOfByte(id >> 8), 1.0f, 1.0f);
            for (int y = 0; y < kHeaderRows; ++y)
                for (int x = 0; x < 80; ++x) f.rgba[std::size_t(y) * kFrameWidth + std::size_t(int(t) * 80 + x)] = code;
            const int x0 = int(t % 4) * kTileWidth, y0 = kHeaderRows + int(t / 4) * kTileHeight;
            for (int y = 0; y < kTileHeight; ++y)
                for (int x = 0; x < kTileWidth; ++x) {
                    const std::size_t src = std::size_t(y) * kTileWidth + std::size_t(x);
                    const std::size_t dst = std::size_t(y0 + y) * kFrameWidth + std::size_t(x0 + x);
                    f.rgba[dst] = img.rgba[src];
                    f.depth[dst] = img.depth[src];
                }
        }
        frames.push_back(std::move(f));
    }
    return frames;
}

int DviPacker::decodeId(const RenderImage& frame, int tile) {
    const glm::vec4 c = frame.rgba[std::size_t(kHeaderRows / 2) * kFrameWidth + std::size_t(tile * 80 + 40)];
    if (c.b < 0.5f) return -1;
    return byteOfLinear(c.r) + 256 * byteOfLinear(c.g);
}

float DviPacker::linearOfByte(int byte) {
    const float s = float(byte) / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

int DviPacker::byteOfLinear(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    return int(std::lround(s * 255.0f));
}

}  // namespace hvx::core
