#pragma once
#include <cstring>
#include <random>
#include <vector>

#include "core/volume/VoxelSource.h"
#include "tests/support/ReferenceOctree.h"

namespace hvx::test {

/// A VoxelSource over values held in memory, typed by the geometry's scalar type. Test only.
class MemoryVoxelSource final : public core::VoxelSource {
public:
    MemoryVoxelSource(core::VolumeGeometry g, DenseVolume v) : g_(std::move(g)), v_(std::move(v)) { g_.dims = v_.dims; }
    const core::VolumeGeometry& geometry() const override { return g_; }
    std::string describe() const override { return "memory volume"; }
    void readSlices(std::uint32_t first, std::uint32_t count, void* dst) override {
        const std::size_t n = std::size_t(g_.dims[0]) * g_.dims[1];
        core::dispatchScalar(g_.scalarType, [&](auto tag) {
            using T = decltype(tag);
            auto* out = static_cast<T*>(dst);
            for (std::size_t i = 0; i < n * count; ++i) out[i] = T(v_.values[first * n + i]);
        });
        ++reads;
    }
    const DenseVolume& values() const { return v_; }
    int reads = 0;

private:
    core::VolumeGeometry g_;
    DenseVolume v_;
};

/// A volume of `dims` whose voxel (i, j, k) holds value(i, j, k), i varying fastest.
template <class F>
DenseVolume generatedVolume(std::array<std::uint32_t, 3> dims, F value) {
    DenseVolume v;
    v.dims = dims;
    v.values.reserve(std::size_t(dims[0]) * dims[1] * dims[2]);
    for (std::uint32_t k = 0; k < dims[2]; ++k)
        for (std::uint32_t j = 0; j < dims[1]; ++j)
            for (std::uint32_t i = 0; i < dims[0]; ++i) v.values.push_back(double(value(i, j, k)));
    return v;
}

/// Random values representable in `type` (labels: 0..labels-1 when labels > 0).
inline DenseVolume randomVolume(std::array<std::uint32_t, 3> dims, core::ScalarType type, unsigned seed,
                                int labels = 0) {
    DenseVolume v;
    v.dims = dims;
    v.values.resize(std::size_t(dims[0]) * dims[1] * dims[2]);
    std::mt19937 rng(seed);
    for (auto& x : v.values) {
        if (labels > 0) x = double(rng() % unsigned(labels));
        else if (type == core::ScalarType::UInt8) x = double(rng() % 256);
        else if (type == core::ScalarType::Int16) x = double(int(rng() % 65536) - 32768);
        else if (type == core::ScalarType::UInt16) x = double(rng() % 65536);
        else x = double(float(std::uniform_real_distribution<double>(-1000.0, 3000.0)(rng)));
    }
    return v;
}

}  // namespace hvx::test
