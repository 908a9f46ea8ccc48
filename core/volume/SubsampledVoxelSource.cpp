#include "core/volume/SubsampledVoxelSource.h"

#include <cstring>

#include "core/base/Error.h"

namespace hvx::core {

SubsampledVoxelSource::SubsampledVoxelSource(std::unique_ptr<VoxelSource> source, std::uint32_t factor)
    : source_(std::move(source)), factor_(factor), geometry_(source_->geometry()) {
    if (factor_ < 1) throw Error("the subsampling factor must be at least 1");
    for (int a = 0; a < 3; ++a) {
        geometry_.dims[std::size_t(a)] = (geometry_.dims[std::size_t(a)] + factor_ - 1) / factor_;
        geometry_.spacing[a] *= double(factor_);
    }
}

std::string SubsampledVoxelSource::describe() const {
    return source_->describe() + " (every " + std::to_string(factor_) + "th voxel)";
}

void SubsampledVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const auto& in = source_->geometry();
    const std::size_t bytes = scalarSize(in.scalarType);
    slice_.resize(std::size_t(in.dims[0]) * in.dims[1] * bytes);
    auto* out = static_cast<std::byte*>(dst);
    const std::size_t nx = geometry_.dims[0], ny = geometry_.dims[1];
    for (std::uint32_t k = 0; k < count; ++k) {
        source_->readSlices((firstSlice + k) * factor_, 1, slice_.data());
        for (std::size_t y = 0; y < ny; ++y)
            for (std::size_t x = 0; x < nx; ++x)
                std::memcpy(out + ((std::size_t(k) * ny + y) * nx + x) * bytes,
                            slice_.data() + ((y * factor_) * in.dims[0] + x * factor_) * bytes, bytes);
    }
}

}  // namespace hvx::core
