#include "dicom/RleDecoder.h"

#include <cstring>

#include "core/base/Error.h"

namespace hvx::dicom {

namespace {
std::uint32_t le32(const std::uint8_t* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}
}  // namespace

void RleDecoder::decode(const std::uint8_t* data, std::size_t size, std::size_t pixels, int bytesPerSample,
                        std::vector<std::uint8_t>& out, const std::string& what) {
    if (size < 64) throw core::Error(what + ": RLE fragment is shorter than its header");
    const std::uint32_t segments = le32(data);
    if (segments != std::uint32_t(bytesPerSample))
        throw core::Error(what + ": RLE header has " + std::to_string(segments) + " segments, expected " +
                          std::to_string(bytesPerSample));
    out.assign(pixels * std::size_t(bytesPerSample), 0);
    for (std::uint32_t s = 0; s < segments; ++s) {
        const std::uint32_t begin = le32(data + 4 + 4 * s);
        const std::uint32_t end = s + 1 < segments ? le32(data + 8 + 4 * s) : std::uint32_t(size);
        if (begin < 64 || begin > end || end > size) throw core::Error(what + ": RLE segment offsets are out of bounds");
        // Segment s holds byte (bytesPerSample - 1 - s) of each sample (most significant first).
        const std::size_t byteIndex = std::size_t(bytesPerSample) - 1 - s;
        std::size_t written = 0;
        std::size_t i = begin;
        while (i < end && written < pixels) {
            const auto n = std::int8_t(data[i++]);
            if (n >= 0) {  // literal run of n + 1 bytes
                const std::size_t count = std::size_t(n) + 1;
                if (i + count > end || written + count > pixels) throw core::Error(what + ": RLE literal run overflows");
                for (std::size_t k = 0; k < count; ++k) out[(written + k) * bytesPerSample + byteIndex] = data[i + k];
                i += count;
                written += count;
            } else if (n != -128) {  // replicate the next byte 1 - n times
                const std::size_t count = std::size_t(1 - n);
                if (i >= end || written + count > pixels) throw core::Error(what + ": RLE replicate run overflows");
                for (std::size_t k = 0; k < count; ++k) out[(written + k) * bytesPerSample + byteIndex] = data[i];
                ++i;
                written += count;
            }
        }
        if (written != pixels) throw core::Error(what + ": RLE segment decodes to too few samples");
    }
}

}  // namespace hvx::dicom
