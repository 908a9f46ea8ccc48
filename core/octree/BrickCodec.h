#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <string_view>
#include <vector>

#include "core/octree/HvoFormat.h"

namespace hvx::core {

/// Lossless compression of brick payloads (zstd, LZ4 or none) and their XXH3-64 checksums.
/// Threading: stateless, safe from any thread.
class BrickCodec {
public:
    /// Compresses `size` bytes into out (replacing its content). `level` is codec specific
    /// (zstd 1..19); 0 picks the codec's fast default. With elementSize > 1 the bytes are first
    /// shuffled into planes (all first bytes, then all second bytes, ...), which makes the
    /// slowly varying high bytes of 16-bit and float samples compress well and fast.
    static void compress(hvo::Codec codec, const void* src, std::size_t size, std::vector<std::byte>& out,
                         int level = 0, std::size_t elementSize = 1);
    /// Decompresses into dst, which must hold exactly `dstSize` bytes, undoing the shuffle of
    /// compress(); returns false when the payload is malformed or decodes to another size.
    static bool decompress(hvo::Codec codec, const void* src, std::size_t size, void* dst, std::size_t dstSize,
                           std::size_t elementSize = 1);
    /// XXH3-64 of a byte range.
    static std::uint64_t checksum(const void* data, std::size_t size);
    /// Parses "zstd", "lz4" or "none"; throws core::Error otherwise.
    static hvo::Codec parse(std::string_view name);
    /// Name of a codec as parse() accepts it.
    static std::string_view name(hvo::Codec codec);
    /// The codecs' libraries as linked: {"zstd", "1.5.4"}, {"LZ4", "1.9.4"}, {"xxHash", "0.8.1"}.
    static std::vector<std::pair<std::string, std::string>> libraryVersions();
};

}  // namespace hvx::core
