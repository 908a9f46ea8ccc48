#include "core/octree/BrickCodec.h"

#include <memory>

#include <lz4.h>
#include <xxhash.h>
#include <zstd.h>

#include <cstring>
#include <limits>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
void shuffle(const std::byte* in, std::byte* out, std::size_t size, std::size_t width) {
    const std::size_t n = size / width;
    if (width == 2) {  // the common case (CT, MR): a loop the compiler vectorises
        auto* lo = reinterpret_cast<std::uint8_t*>(out);
        auto* hi = lo + n;
        for (std::size_t i = 0; i < n; ++i) {
            std::uint16_t v;
            std::memcpy(&v, in + 2 * i, 2);
            lo[i] = std::uint8_t(v & 0xffu);
            hi[i] = std::uint8_t(v >> 8);
        }
        return;
    }
    for (std::size_t b = 0; b < width; ++b) {
        std::byte* plane = out + b * n;
        for (std::size_t i = 0; i < n; ++i) plane[i] = in[i * width + b];
    }
}

void unshuffle(const std::byte* in, std::byte* out, std::size_t size, std::size_t width) {
    const std::size_t n = size / width;
    if (width == 2) {
        const auto* lo = reinterpret_cast<const std::uint8_t*>(in);
        const auto* hi = lo + n;
        for (std::size_t i = 0; i < n; ++i) {
            const auto v = std::uint16_t(lo[i] | (hi[i] << 8));
            std::memcpy(out + 2 * i, &v, 2);
        }
        return;
    }
    for (std::size_t b = 0; b < width; ++b) {
        const std::byte* plane = in + b * n;
        for (std::size_t i = 0; i < n; ++i) out[i * width + b] = plane[i];
    }
}
}  // namespace

void BrickCodec::compress(hvo::Codec codec, const void* src, std::size_t size, std::vector<std::byte>& out,
                          int level, std::size_t elementSize) {
    if (elementSize > 1 && size % elementSize == 0) {
        thread_local std::vector<std::byte> planes;
        planes.resize(size);
        shuffle(static_cast<const std::byte*>(src), planes.data(), size, elementSize);
        compress(codec, planes.data(), size, out, level, 1);
        return;
    }
    switch (codec) {
    case hvo::Codec::None:
        out.resize(size);
        if (size) std::memcpy(out.data(), src, size);
        return;
    case hvo::Codec::Zstd: {
        out.resize(ZSTD_compressBound(size));
        // One context per thread, freed when the thread ends (a worker pool's threads come and go).
        thread_local const std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> ctx(ZSTD_createCCtx(), &ZSTD_freeCCtx);
        if (!ctx) throw Error("zstd compression failed: no memory for its context");
        const std::size_t n = ZSTD_compressCCtx(ctx.get(), out.data(), out.size(), src, size, level != 0 ? level : 1);
        if (ZSTD_isError(n)) throw Error(std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
        out.resize(n);
        return;
    }
    case hvo::Codec::Lz4: {
        if (size > std::size_t(LZ4_MAX_INPUT_SIZE)) throw Error("brick too large for LZ4");
        out.resize(std::size_t(LZ4_compressBound(int(size))));
        const int n = LZ4_compress_default(static_cast<const char*>(src), reinterpret_cast<char*>(out.data()),
                                           int(size), int(out.size()));
        if (n <= 0) throw Error("LZ4 compression failed");
        out.resize(std::size_t(n));
        return;
    }
    }
    throw Error("unknown codec");
}

bool BrickCodec::decompress(hvo::Codec codec, const void* src, std::size_t size, void* dst, std::size_t dstSize,
                            std::size_t elementSize) {
    if (elementSize > 1 && dstSize % elementSize == 0) {
        thread_local std::vector<std::byte> planes;
        planes.resize(dstSize);
        if (!decompress(codec, src, size, planes.data(), dstSize, 1)) return false;
        unshuffle(planes.data(), static_cast<std::byte*>(dst), dstSize, elementSize);
        return true;
    }
    switch (codec) {
    case hvo::Codec::None:
        if (size != dstSize) return false;
        if (size) std::memcpy(dst, src, size);
        return true;
    case hvo::Codec::Zstd: {
        thread_local const std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(), &ZSTD_freeDCtx);
        if (!ctx) return false;
        const std::size_t n = ZSTD_decompressDCtx(ctx.get(), dst, dstSize, src, size);
        return !ZSTD_isError(n) && n == dstSize;
    }
    case hvo::Codec::Lz4: {
        if (size > std::size_t(std::numeric_limits<int>::max()) || dstSize > std::size_t(std::numeric_limits<int>::max()))
            return false;
        const int n = LZ4_decompress_safe(static_cast<const char*>(src), static_cast<char*>(dst), int(size), int(dstSize));
        return n >= 0 && std::size_t(n) == dstSize;
    }
    }
    return false;
}

std::uint64_t BrickCodec::checksum(const void* data, std::size_t size) { return XXH3_64bits(data, size); }

hvo::Codec BrickCodec::parse(std::string_view name) {
    if (name == "zstd") return hvo::Codec::Zstd;
    if (name == "lz4") return hvo::Codec::Lz4;
    if (name == "none") return hvo::Codec::None;
    throw Error("unknown codec '" + std::string(name) + "' (supported: zstd, lz4, none)");
}

std::string_view BrickCodec::name(hvo::Codec codec) {
    switch (codec) {
    case hvo::Codec::None: return "none";
    case hvo::Codec::Zstd: return "zstd";
    case hvo::Codec::Lz4: return "lz4";
    }
    return "unknown";
}

std::vector<std::pair<std::string, std::string>> BrickCodec::libraryVersions() {
    const unsigned xxh = XXH_versionNumber();
    return {{"zstd", ZSTD_versionString()},
            {"LZ4", LZ4_versionString()},
            {"xxHash", std::to_string(xxh / 10000) + "." + std::to_string(xxh / 100 % 100) + "." + std::to_string(xxh % 100)}};
}

}  // namespace hvx::core
