#include "core/octree/SplitVoxelGrid.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "core/base/Error.h"
#include "core/base/ThreadPool.h"
#include "core/octree/SplitVoxelWindows.h"
#include "core/volume/ScalarType.h"

namespace hvx::core {

namespace {
std::uint32_t ceilDiv(std::uint32_t a, std::uint32_t b) { return (a + b - 1) / b; }

/// Fits every cell of `grid` on the shared pool: `fill` writes cell (x, y, z)'s window.
void fitAll(SplitVoxelGrid& grid, const SplitVoxelFitter& fitter, std::uint32_t S, std::uint32_t M, JobContext& job,
            const std::function<void(std::uint32_t, std::uint32_t, std::uint32_t, float*)>& fill) {
    const auto d = grid.dims();
    const std::uint32_t E = S + 2 * M;
    const std::size_t rows = std::size_t(d[1]) * d[2];
    std::atomic<std::size_t> done{0};
    ThreadPool::shared().parallelFor(rows, [&](std::size_t begin, std::size_t end) {
        std::vector<float> window(std::size_t(E) * E * E);
        for (std::size_t r = begin; r < end; ++r) {
            if (job.cancelled()) return;
            const auto y = std::uint32_t(r % d[1]), z = std::uint32_t(r / d[1]);
            for (std::uint32_t x = 0; x < d[0]; ++x) {
                fill(x, y, z, window.data());
                grid.at(x, y, z) = fitter.fit(window.data(), S, M);
            }
            const std::size_t n = ++done;
            if (n % 64 == 0) job.report(double(n) / double(rows), "fitting split-voxels");
        }
    }, 4);
    job.throwIfCancelled();
}
}  // namespace

SplitVoxelGrid::SplitVoxelGrid(Dims cells, std::uint32_t cellVoxels)
    : dims_(cells), cellVoxels_(cellVoxels), cells_(std::size_t(cells[0]) * cells[1] * cells[2]) {}

SplitVoxelGrid SplitVoxelGrid::build(VoxelSource& source, const SplitVoxelOptions& options, JobContext& job) {
    options.validate();
    const auto& g = source.geometry();
    if (g.scalarType == ScalarType::Float32)
        throw Error(source.describe() + ": split-voxels need 8- or 16-bit integer values (this volume holds floats)");
    const auto d = g.dims;
    // The volume as floats (stored values), read slab by slab.
    std::vector<float> volume(g.voxelCount());
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    const std::size_t slice = std::size_t(d[0]) * d[1];
    std::vector<std::uint8_t> slab(slice * scalarSize(g.scalarType) * 16);
    for (std::uint32_t z = 0; z < d[2]; z += 16) {
        const std::uint32_t n = std::min<std::uint32_t>(16, d[2] - z);
        source.readSlices(z, n, slab.data());
        float* out = volume.data() + slice * z;
        for (std::size_t a = 0; a < slice * n; ++a) {
            switch (g.scalarType) {
                case ScalarType::UInt8: out[a] = float(slab[a]); break;
                case ScalarType::Int16: { std::int16_t v; std::memcpy(&v, &slab[2 * a], 2); out[a] = float(v); break; }
                default: { std::uint16_t v; std::memcpy(&v, &slab[2 * a], 2); out[a] = float(v); break; }
            }
            lo = std::min(lo, out[a]);
            hi = std::max(hi, out[a]);
        }
        job.throwIfCancelled();
    }
    const std::uint32_t N = options.n, M = options.overlap;
    SplitVoxelGrid grid({ceilDiv(d[0], N), ceilDiv(d[1], N), ceilDiv(d[2], N)}, N);
    SplitVoxelOptions resolved = options;
    if (!resolved.threshold) resolved.threshold = 0.02 * double(hi - lo);
    grid.threshold_ = *resolved.threshold;
    const SplitVoxelFitter fitter(resolved);
    const auto voxel = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
        return volume[(std::size_t(k) * d[1] + j) * d[0] + i];
    };
    fitAll(grid, fitter, N, M, job, [&](std::uint32_t x, std::uint32_t y, std::uint32_t z, float* w) {
        split::fillVoxelWindow(voxel, d, N, M, x, y, z, w);
    });
    return grid;
}

SplitVoxelGrid SplitVoxelGrid::coarser(const SplitVoxelOptions& options, JobContext& job) const {
    options.validate();
    SplitVoxelGrid grid({ceilDiv(dims_[0], 2), ceilDiv(dims_[1], 2), ceilDiv(dims_[2], 2)}, cellVoxels_ * 2);
    SplitVoxelOptions resolved = options;
    if (!resolved.threshold) resolved.threshold = threshold_;  // level 0's, found in the volume
    grid.threshold_ = *resolved.threshold;
    const SplitVoxelFitter fitter(resolved);
    const auto cell = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) -> const SplitVoxel& { return at(x, y, z); };
    fitAll(grid, fitter, split::coarseInterior(), split::coarseOverlap(options.overlap), job,
           [&](std::uint32_t x, std::uint32_t y, std::uint32_t z, float* w) {
               split::fillCellWindow(cell, dims_, options.overlap, x, y, z, w);
           });
    return grid;
}

float SplitVoxelGrid::valueAt(const glm::dvec3& index) const {
    const glm::dvec3 c = glm::clamp((index + 0.5) / double(cellVoxels_), glm::dvec3(0.0),
                                    glm::dvec3(dims_[0], dims_[1], dims_[2]) - 1e-6);
    const glm::uvec3 cell(c);
    return at(cell.x, cell.y, cell.z).valueAt(glm::vec3(c - glm::dvec3(cell)));
}

std::size_t SplitVoxelGrid::splitCells() const {
    return std::size_t(std::count_if(cells_.begin(), cells_.end(), [](const SplitVoxel& v) { return !v.isUniform(); }));
}

}  // namespace hvx::core
