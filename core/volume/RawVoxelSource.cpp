#include "core/volume/RawVoxelSource.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "core/base/Error.h"

namespace hvx::core {

VolumeGeometry RawVoxelSource::Options::geometry() const {
    VolumeGeometry g;
    g.dims = dims;
    g.scalarType = type;
    g.spacing = spacing;
    g.origin = origin;
    g.direction = direction;
    g.modality = modality;
    return g;
}

RawVoxelSource::Options RawVoxelSource::described(const VolumeGeometry& g, bool bigEndian, std::uint64_t headerBytes,
                                                  std::vector<std::string> warnings) {
    Options o;
    o.dims = g.dims;
    o.type = g.scalarType;
    o.bigEndian = bigEndian && scalarSize(o.type) > 1;
    o.headerBytes = headerBytes;
    o.spacing = g.spacing;
    o.origin = g.origin;
    o.direction = g.direction;
    o.modality = g.modality;
    o.warnings = std::move(warnings);
    return o;
}

RawVoxelSource::RawVoxelSource(std::string path, const Options& options)
    : path_(std::move(path)), options_(options), geometry_(options.geometry()) {
    geometry_.validate(path_);
    fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw Error(path_ + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd_);
        throw Error(path_ + ": not a regular file");
    }
    const std::uint64_t need = options.headerBytes + geometry_.byteSize();
    if (std::uint64_t(st.st_size) != need) {
        ::close(fd_);
        throw Error(path_ + ": dimensions " + std::to_string(options.dims[0]) + "x" +
                    std::to_string(options.dims[1]) + "x" + std::to_string(options.dims[2]) + " " +
                    std::string(scalarName(options.type)) + " need " + std::to_string(need) +
                    " bytes but the file has " + std::to_string(st.st_size));
    }
}

RawVoxelSource::~RawVoxelSource() {
    if (fd_ >= 0) ::close(fd_);
}

void RawVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const std::size_t width = scalarSize(geometry_.scalarType);
    const std::uint64_t sliceBytes = std::uint64_t(geometry_.dims[0]) * geometry_.dims[1] * width;
    std::uint64_t offset = options_.headerBytes + sliceBytes * firstSlice;
    std::uint64_t remaining = sliceBytes * count;
    auto* out = static_cast<char*>(dst);
    while (remaining > 0) {
        const std::size_t chunk = std::size_t(std::min<std::uint64_t>(remaining, 1u << 30));
        const ssize_t got = ::pread(fd_, out, chunk, off_t(offset));
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw Error(path_ + ": read failed (" + std::strerror(errno) + ")");
        if (got == 0) throw Error(path_ + ": file is truncated at byte " + std::to_string(offset));
        out += got;
        offset += std::uint64_t(got);
        remaining -= std::uint64_t(got);
    }
    if (options_.bigEndian && width > 1) swapByteOrder(dst, std::size_t(sliceBytes * count / width), width);
}

}  // namespace hvx::core
