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
    g.scalarType = storedTypeOf(element);
    g.spacing = spacing;
    g.origin = origin;
    g.direction = direction;
    g.modality = modality;
    g.orientationAssumed = orientationAssumed;
    g.spacingAssumed = spacingAssumed;
    return g;
}

RawVoxelSource::Options RawVoxelSource::described(const VolumeGeometry& g, FileElement element, bool bigEndian,
                                                  std::uint64_t headerBytes, std::vector<std::string> warnings,
                                                  const std::string& file) {
    Options o;
    o.dims = g.dims;
    o.element = element;
    o.bigEndian = bigEndian && elementSize(element) > 1;
    o.headerBytes = headerBytes;
    o.spacing = g.spacing;
    o.origin = g.origin;
    o.direction = g.direction;
    o.modality = g.modality;
    o.orientationAssumed = g.orientationAssumed;
    o.spacingAssumed = g.spacingAssumed;
    o.warnings = std::move(warnings);
    if (const auto w = conversionWarning(element); !w.empty()) o.warnings.push_back(file + ": " + w);
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
    const std::uint64_t need = options.headerBytes + geometry_.voxelCount() * elementSize(options.element);
    if (std::uint64_t(st.st_size) < need || (!options.trailingBytes && std::uint64_t(st.st_size) != need)) {
        ::close(fd_);
        throw Error(path_ + ": dimensions " + std::to_string(options.dims[0]) + "x" +
                    std::to_string(options.dims[1]) + "x" + std::to_string(options.dims[2]) + " " +
                    std::string(elementName(options.element)) + " need " + std::to_string(need) +
                    " bytes but the file has " + std::to_string(st.st_size));
    }
}

RawVoxelSource::~RawVoxelSource() {
    if (fd_ >= 0) ::close(fd_);
}

void RawVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const std::uint64_t sliceVoxels = std::uint64_t(geometry_.dims[0]) * geometry_.dims[1];
    std::uint64_t offset = options_.headerBytes + sliceVoxels * elementSize(options_.element) * firstSlice;
    decodeSlices(options_.element, options_.bigEndian, sliceVoxels, firstSlice, count, buffer_, dst,
                 [&](unsigned char* into, std::uint64_t bytes) {
                     readBytes(offset, bytes, into);
                     offset += bytes;
                 }, path_);
}

void RawVoxelSource::readBytes(std::uint64_t offset, std::uint64_t bytes, unsigned char* out) {
    while (bytes > 0) {
        const std::size_t chunk = std::size_t(std::min<std::uint64_t>(bytes, 1u << 30));
        const ssize_t got = ::pread(fd_, out, chunk, off_t(offset));
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw Error(path_ + ": read failed (" + std::strerror(errno) + ")");
        if (got == 0) throw Error(path_ + ": file is truncated at byte " + std::to_string(offset));
        out += got;
        offset += std::uint64_t(got);
        bytes -= std::uint64_t(got);
    }
}

}  // namespace hvx::core
