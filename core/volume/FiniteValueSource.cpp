#include "core/volume/FiniteValueSource.h"

#include <cmath>

#include "core/base/Error.h"

namespace hvx::core {

std::unique_ptr<VoxelSource> FiniteValueSource::wrap(std::unique_ptr<VoxelSource> source) {
    if (source->geometry().scalarType != ScalarType::Float32) return source;
    return std::make_unique<FiniteValueSource>(std::move(source));
}

std::string FiniteValueSource::nonFinite(const float* v, std::size_t count) {
    bool finite = true;
    for (std::size_t i = 0; i < count; ++i) finite &= std::isfinite(v[i]);  // branch-free: vectorises
    if (finite) return {};
    std::size_t nan = 0, inf = 0;
    for (std::size_t i = 0; i < count; ++i) {
        nan += std::isnan(v[i]);
        inf += std::isinf(v[i]);
    }
    std::string what;
    if (nan) what = std::to_string(nan) + (nan == 1 ? " NaN (not-a-number) value" : " NaN (not-a-number) values");
    if (inf) what += (nan ? " and " : "") + std::to_string(inf) + (inf == 1 ? " infinite value" : " infinite values");
    return what;
}

void FiniteValueSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    source_->readSlices(firstSlice, count, dst);
    const auto& dims = source_->geometry().dims;
    const std::size_t sliceVoxels = std::size_t(dims[0]) * dims[1];
    const auto* v = static_cast<const float*>(dst);
    for (std::uint32_t s = 0; s < count; ++s, v += sliceVoxels)
        if (const std::string what = nonFinite(v, sliceVoxels); !what.empty())
            throw Error(describe() + ": slice " + std::to_string(firstSlice + s) + " holds " + what +
                        ": Holovox reads only volumes whose every voxel is a number (replace them first, e.g. "
                        "with fslmaths IN -nan OUT)");
}

}  // namespace hvx::core
