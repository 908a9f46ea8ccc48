#include "core/volume/InflatedVoxelSource.h"

#include <sys/stat.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/base/Error.h"

namespace hvx::core {

struct InflatedVoxelSource::Stream {
    std::FILE* file = nullptr;
    z_stream z{};
    bool started = false;
    bool ended = false;  // inflate reached the stream's end (its check verified)
    std::vector<unsigned char> in = std::vector<unsigned char>(1u << 18);
    /// Gives inflate more input; false at the end of the file.
    bool refill() {
        if (z.avail_in > 0) return true;
        const std::size_t got = std::fread(in.data(), 1, in.size(), file);
        z.next_in = in.data();
        z.avail_in = uInt(got);
        return got > 0;
    }
    ~Stream() {
        if (started) inflateEnd(&z);
        if (file) std::fclose(file);
    }
};

InflatedVoxelSource::InflatedVoxelSource(std::string path, const RawVoxelSource::Options& options)
    : path_(std::move(path)), options_(options), geometry_(options.geometry()), stream_(std::make_unique<Stream>()) {
    geometry_.validate(path_);
    stream_->file = std::fopen(path_.c_str(), "rbe");
    if (!stream_->file) throw Error(path_ + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(::fileno(stream_->file), &st) == 0 && S_ISREG(st.st_mode)) {
        const std::uint64_t size = std::uint64_t(st.st_size);
        const double voxelBytes = double(geometry_.voxelCount()) * double(elementSize(options_.element));
        checkDeflatedCanHold(path_, size > options_.headerBytes ? size - options_.headerBytes : 0,
                             options_.inflatedTotal ? double(options_.inflatedTotal) : voxelBytes);
    }
    restart();
}

void InflatedVoxelSource::checkDeflatedCanHold(const std::string& file, std::uint64_t compressedBytes, double bytes) {
    constexpr double kMostDeflateRatio = 1032.0;
    if (bytes > double(compressedBytes) * kMostDeflateRatio)
        throw Error(file + ": its header needs " + std::to_string(std::uint64_t(bytes)) + " bytes once inflated, more than its " +
                    std::to_string(compressedBytes) + " bytes of compressed data can hold (deflate packs at most 1032 bytes into one)");
}

InflatedVoxelSource::~InflatedVoxelSource() = default;

void InflatedVoxelSource::restart() {
    Stream& s = *stream_;
    if (s.started) inflateEnd(&s.z);
    s.started = false;
    s.z = z_stream{};
    if (fseeko(s.file, off_t(options_.headerBytes), SEEK_SET) != 0)
        throw Error(path_ + ": cannot seek to its compressed data (" + std::strerror(errno) + ")");
    if (inflateInit2(&s.z, 15 + 32) != Z_OK)  // 15 + 32: a zlib or a gzip header, whichever it is
        throw Error(path_ + ": cannot start zlib");
    s.started = true;
    s.ended = false;
    position_ = 0;
}

void InflatedVoxelSource::inflateInto(unsigned char* dst, std::uint64_t bytes) {
    Stream& s = *stream_;
    unsigned char scratch[1u << 16];
    const std::uint64_t sliceBytes = std::uint64_t(geometry_.dims[0]) * geometry_.dims[1] * elementSize(options_.element);
    auto where = [&] {
        const std::uint64_t volumeBytes = sliceBytes * geometry_.dims[2];
        const std::uint64_t at = position_ - options_.inflatedSkip;  // within this volume when reading it
        if (options_.inflatedTotal && (position_ < options_.inflatedSkip || at >= volumeBytes))
            return " in volume " + std::to_string(position_ / volumeBytes + 1);
        return " at slice " + std::to_string(at / sliceBytes) + " of " + std::to_string(geometry_.dims[2]);
    };
    while (bytes > 0) {
        const std::uint64_t step = std::min<std::uint64_t>(bytes, dst ? (1u << 30) : sizeof scratch);
        s.z.next_out = dst ? dst : scratch;
        s.z.avail_out = uInt(step);
        while (s.z.avail_out > 0) {
            if (!s.refill()) throw Error(path_ + ": its compressed data ends" + where() + " (the file is truncated)");
            const uInt before = s.z.avail_out;
            const int r = inflate(&s.z, Z_NO_FLUSH);
            position_ += before - s.z.avail_out;
            if (r == Z_STREAM_END) s.ended = true;
            if (r == Z_STREAM_END && s.z.avail_out > 0)
                throw Error(path_ + ": its compressed data holds fewer voxels than its header describes (it ends" + where() + ")");
            if (r != Z_OK && r != Z_STREAM_END && r != Z_BUF_ERROR)
                throw Error(path_ + ": its compressed data is corrupt" + where() + " (zlib: " +
                            (s.z.msg ? s.z.msg : std::to_string(r)) + ")");
        }
        if (dst) dst += step;
        bytes -= step;
    }
}

void InflatedVoxelSource::checkEnd() {
    // The stream's own check (zlib's Adler-32, gzip's CRC-32) comes after the data: inflate up to
    // it, so that data changed in the middle of the stream is caught, not shown.
    Stream& s = *stream_;
    unsigned char extra[1];
    while (!s.ended) {
        if (!s.refill()) throw Error(path_ + ": its compressed data ends before its check (the file is truncated)");
        s.z.next_out = extra;
        s.z.avail_out = 1;
        const int r = inflate(&s.z, Z_NO_FLUSH);
        if (r == Z_STREAM_END && s.z.avail_out == 1) s.ended = true;
        if (s.z.avail_out == 0)
            throw Error(path_ + ": its compressed data holds more voxels than its header describes");
        if (r != Z_OK && r != Z_STREAM_END && r != Z_BUF_ERROR)
            throw Error(path_ + ": its compressed data is corrupt (zlib: " + (s.z.msg ? s.z.msg : std::to_string(r)) + ")");
    }
}

void InflatedVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const std::uint64_t sliceBytes = std::uint64_t(geometry_.dims[0]) * geometry_.dims[1] * elementSize(options_.element);
    const std::uint64_t skip = options_.inflatedSkip;  // the volumes before this one, in a 4-D file
    const std::uint64_t total = options_.inflatedTotal ? options_.inflatedTotal : skip + sliceBytes * geometry_.dims[2];
    const std::uint64_t at = skip + sliceBytes * firstSlice;
    if (at < position_) restart();
    inflateInto(nullptr, at - position_);
    decodeSlices(options_.element, options_.bigEndian, std::uint64_t(geometry_.dims[0]) * geometry_.dims[1], firstSlice,
                 count, buffer_, dst, [&](unsigned char* into, std::uint64_t bytes) {
                     inflateInto(into, bytes);
                     if (position_ == total) checkEnd();  // the last volume's last slice: the stream's check follows
                 }, path_);
}

}  // namespace hvx::core
