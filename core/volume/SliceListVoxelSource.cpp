#include "core/volume/SliceListVoxelSource.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include "core/base/Error.h"
#include "core/volume/ScalarType.h"

namespace hvx::core {

SliceListVoxelSource::SliceListVoxelSource(std::vector<std::string> files, const RawVoxelSource::Options& options,
                                           std::string describe)
    : files_(std::move(files)), options_(options), slice_(options), geometry_(options.geometry()),
      describe_(std::move(describe)) {
    geometry_.validate(describe_);
    if (files_.size() != geometry_.dims[2])
        throw Error(describe_ + ": " + std::to_string(files_.size()) + " slice files for " +
                    std::to_string(geometry_.dims[2]) + " slices");
    slice_.dims[2] = 1;
    slice_.headerBytes = 0;
    slice_.trailingBytes = false;
    slice_.warnings.clear();
    const std::uint64_t bytes = std::uint64_t(geometry_.dims[0]) * geometry_.dims[1] * elementSize(options.element);
    for (std::size_t k = 0; k < files_.size(); ++k) {
        struct stat st {};
        if (::stat(files_[k].c_str(), &st) != 0)
            throw Error(describe_ + ": slice " + std::to_string(k) + "'s file " + files_[k] + " cannot be read (" +
                        std::strerror(errno) + ")");
        if (!S_ISREG(st.st_mode) || std::uint64_t(st.st_size) != bytes)
            throw Error(describe_ + ": slice " + std::to_string(k) + "'s file " + files_[k] + " holds " +
                        std::to_string(st.st_size) + " bytes, not the " + std::to_string(bytes) + " of one slice");
    }
}

SliceListVoxelSource::~SliceListVoxelSource() = default;

void SliceListVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const std::uint64_t sliceBytes = std::uint64_t(geometry_.dims[0]) * geometry_.dims[1] * scalarSize(geometry_.scalarType);
    auto* out = static_cast<unsigned char*>(dst);
    for (std::uint32_t k = 0; k < count; ++k) {
        if (std::uint64_t(firstSlice) + k >= files_.size())
            throw Error(describe_ + ": slice " + std::to_string(firstSlice + k) + " is past the last");
        // Opened for the slice and closed after it: a stack of thousands of files holds no
        // descriptor between reads.
        RawVoxelSource file(files_[firstSlice + k], slice_);
        file.readSlices(0, 1, out + k * sliceBytes);
    }
}

}  // namespace hvx::core
