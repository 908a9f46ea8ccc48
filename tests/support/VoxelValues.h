#pragma once
// Every voxel of a source, read in one go, as doubles: stored values, or physical ones
// (stored * slope + intercept). Test only.
#include <vector>

#include "core/volume/VoxelSource.h"

namespace hvx::test {

/// Every voxel of a source as stored, read in one go; T must be its scalar type.
template <class T>
std::vector<T> readAll(core::VoxelSource& s) {
    const auto& d = s.geometry().dims;
    std::vector<T> v(static_cast<std::size_t>(d[0]) * d[1] * d[2]);
    s.readSlices(0, d[2], v.data());
    return v;
}

inline std::vector<double> voxelValues(core::VoxelSource& s, bool physical = false) {
    const auto& g = s.geometry();
    const std::size_t n = std::size_t(g.dims[0]) * g.dims[1] * g.dims[2];
    std::vector<double> out(n);
    core::dispatchScalar(g.scalarType, [&](auto tag) {
        using T = decltype(tag);
        std::vector<T> buf(n);
        s.readSlices(0, g.dims[2], buf.data());
        for (std::size_t i = 0; i < n; ++i)
            out[i] = physical ? double(buf[i]) * g.rescaleSlope + g.rescaleIntercept : double(buf[i]);
    });
    return out;
}

}  // namespace hvx::test
