#include "core/octree/SplitVoxelOctreeBuilder.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <deque>
#include <functional>
#include <limits>
#include <vector>

#include "core/base/AtomicFileWriter.h"
#include "core/base/Error.h"
#include "core/octree/BrickCodec.h"
#include "core/octree/HvoHeader.h"
#include "core/octree/OctreeLayout.h"
#include "core/octree/SplitVoxelWindows.h"
#include "core/base/ThreadPool.h"

namespace hvx::core {

SplitVoxelOctreeBuilder::SplitVoxelOctreeBuilder(BuildOptions build, SplitVoxelOptions split)
    : build_(std::move(build)), split_(split) {
    if (build_.brickSize < 4 || build_.brickSize > 256) throw Error("brick size must be between 4 and 256 cells");
    if (build_.lossy8) throw Error("split-voxels keep their values exactly: --lossy8 does not apply");
    if (build_.emptyBelow) throw Error("split-voxel octrees store every node: --empty-below does not apply");
    split_.validate();
}

namespace {
/// One level's cells, row by row along z, holding only the rows still needed: by the coarser
/// level's fits (SplitVoxelWindows' finerRows) and by this level's bricks not yet written.
struct LevelRows {
    split::Dims dims{};
    std::uint32_t base = 0;  // the row rows.front() holds
    std::deque<std::vector<SplitVoxel>> rows;
    std::uint32_t nextBrickRow = 0;  // bricks of rows below it are written
    std::uint32_t fitted() const { return base + std::uint32_t(rows.size()); }
    const SplitVoxel& at(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
        return rows[z - base][std::size_t(y) * dims[0] + x];
    }
    void dropBefore(std::uint32_t z) {
        while (base < z && !rows.empty()) {
            rows.pop_front();
            ++base;
        }
    }
};

/// Fits one row (along z) of cells on the shared pool: `fill` writes cell (x, y)'s window.
template <class Fill>
std::vector<SplitVoxel> fitRow(const split::Dims& dims, const SplitVoxelFitter& fitter, std::uint32_t S, std::uint32_t M,
                               JobContext& job, const Fill& fill) {
    std::vector<SplitVoxel> row(static_cast<std::size_t>(dims[0]) * dims[1]);
    const std::uint32_t E = S + 2 * M;
    ThreadPool::shared().parallelFor(dims[1], [&](std::size_t begin, std::size_t end) {
        std::vector<float> window(std::size_t(E) * E * E);
        for (std::size_t y = begin; y < end && !job.cancelled(); ++y)
            for (std::uint32_t x = 0; x < dims[0]; ++x) {
                fill(x, std::uint32_t(y), window.data());
                row[y * dims[0] + x] = fitter.fit(window.data(), S, M);
            }
    }, 4);
    job.throwIfCancelled();
    return row;
}

float storedValue(const std::uint8_t* slab, std::size_t i, ScalarType type) {
    switch (type) {
        case ScalarType::UInt8: return float(slab[i]);
        case ScalarType::Int16: { std::int16_t v; std::memcpy(&v, slab + 2 * i, 2); return float(v); }
        default: { std::uint16_t v; std::memcpy(&v, slab + 2 * i, 2); return float(v); }
    }
}
}  // namespace

BuildReport SplitVoxelOctreeBuilder::build(VoxelSource& source, const std::string& output, JobContext& job) {
    const auto t0 = std::chrono::steady_clock::now();
    const VolumeGeometry& g = source.geometry();
    g.validate(source.describe());
    if (g.scalarType == ScalarType::Float32)
        throw Error(source.describe() + ": split-voxels need 8- or 16-bit integer values (this volume holds floats)");
    SplitVoxelOptions split = split_;
    split.labels = split_.labels || build_.labels || g.isLabel;
    const auto& d = g.dims;
    const std::size_t slice = std::size_t(d[0]) * d[1], valueBytes = scalarSize(g.scalarType);
    std::vector<std::uint8_t> slab(slice * valueBytes * 16);
    // Intensities without a threshold: 2 % of the stored range found in the volume (one read
    // through it first, as SplitVoxelGrid::build finds it).
    if (!split.labels && !split.threshold) {
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        for (std::uint32_t z = 0; z < d[2]; z += 16) {
            const std::uint32_t n = std::min<std::uint32_t>(16, d[2] - z);
            source.readSlices(z, n, slab.data());
            for (std::size_t a = 0; a < slice * n; ++a) {
                const float v = storedValue(slab.data(), a, g.scalarType);
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
            job.report(0.1 * double(z + n) / double(d[2]), "finding the value range");
        }
        split.threshold = 0.02 * double(hi - lo);
    }
    const std::uint32_t N = split.n, M = split.overlap;
    // The cell grid as a volume: what the layout, the header and every traversal see.
    VolumeGeometry cells = g;
    const double n = double(N);
    for (int a = 0; a < 3; ++a) {
        cells.dims[std::size_t(a)] = (d[std::size_t(a)] + N - 1) / N;
        cells.spacing[a] = g.spacing[a] * n;
    }
    cells.origin = glm::dvec3(g.indexToPatient() * glm::dvec4(glm::dvec3((n - 1.0) / 2.0), 1.0));
    cells.isLabel = split.labels;
    const OctreeLayout layout(cells.dims, build_.brickSize);
    const int levelCount = layout.levelCount();

    BuildOptions opt = build_;
    opt.border = 0;
    opt.labels = split.labels;
    hvo::FileHeader header = hvo::startHeader(cells, opt, levelCount);
    header.version = hvo::kVersionSplitVoxels;
    header.flags = (header.flags & ~hvo::FileShuffled) | hvo::FileSplitVoxels;
    for (int a = 0; a < 3; ++a) header.split.sourceDims[a] = d[std::size_t(a)];
    header.split.n = std::uint16_t(N);
    header.split.overlap = std::uint16_t(M);
    AtomicFileWriter out(output);
    out.append(&header, sizeof header);

    // Each brick row's nodes, per level.
    std::vector<hvo::NodeRecord> nodes = layout.nodes();
    std::vector<std::vector<std::vector<std::uint32_t>>> rowNodes(static_cast<std::size_t>(levelCount));
    for (int l = 0; l < levelCount; ++l) rowNodes[std::size_t(l)].resize(layout.levelNodes(l)[2]);
    for (std::uint32_t id = 0; id < nodes.size(); ++id) rowNodes[nodes[id].level][nodes[id].z].push_back(id);
    std::vector<LevelRows> levels(static_cast<std::size_t>(levelCount));
    for (int l = 0; l < levelCount; ++l) levels[std::size_t(l)].dims = layout.levelDims(l);

    const bool isSigned = g.scalarType == ScalarType::Int16;
    const std::size_t cellBytes = SplitVoxel::encodedSize(valueBytes);
    const std::uint32_t B = build_.brickSize;
    std::vector<std::uint8_t> raw(std::size_t(B) * B * B * cellBytes);
    std::vector<std::byte> packed;
    const auto writeBricks = [&](const LevelRows& level, std::uint32_t brickRow, const std::vector<std::uint32_t>& ids) {
        const auto& ld = level.dims;
        for (const std::uint32_t id : ids) {
            auto& rec = nodes[id];
            float lo = std::numeric_limits<float>::infinity(), hi = -lo;
            std::uint8_t* at = raw.data();
            for (std::uint32_t z = 0; z < B; ++z)
                for (std::uint32_t y = 0; y < B; ++y)
                    for (std::uint32_t x = 0; x < B; ++x, at += cellBytes) {
                        // Cells past the grid repeat its last ones, as voxel bricks repeat their faces.
                        const SplitVoxel& v = level.at(std::min(rec.x * B + x, ld[0] - 1), std::min(rec.y * B + y, ld[1] - 1),
                                                       std::min(brickRow * B + z, ld[2] - 1));
                        v.encode(at, valueBytes, isSigned);
                        lo = std::min({lo, v.front, v.back});
                        hi = std::max({hi, v.front, v.back});
                    }
            rec.minValue = lo;
            rec.maxValue = hi;
            BrickCodec::compress(hvo::Codec(header.codec), raw.data(), raw.size(), packed, build_.codecLevel);
            rec.payloadSize = std::uint32_t(packed.size());
            rec.checksum = BrickCodec::checksum(packed.data(), packed.size());
            rec.payloadOffset = out.append(packed.data(), packed.size());
            header.payloadBytes += packed.size();
            header.rawBrickBytes += raw.size();
        }
    };

    const SplitVoxelFitter fitter(split);
    // After rows arrive at level l: write its bricks whose rows are all there, fit the coarser
    // level's rows that can be, and forget the rows neither needs any more.
    const std::function<void(int)> advance = [&](int l) {
        auto& level = levels[std::size_t(l)];
        const std::uint32_t rowsAll = level.dims[2];
        while (level.nextBrickRow < rowNodes[std::size_t(l)].size() &&
               level.fitted() >= std::min(rowsAll, (level.nextBrickRow + 1) * B)) {
            writeBricks(level, level.nextBrickRow, rowNodes[std::size_t(l)][level.nextBrickRow]);
            ++level.nextBrickRow;
        }
        std::uint32_t keepFrom = level.nextBrickRow * B;
        if (l + 1 < levelCount) {
            auto& coarse = levels[std::size_t(l) + 1];
            while (coarse.fitted() < coarse.dims[2] && split::finerRows(coarse.fitted(), M, rowsAll)[1] < level.fitted()) {
                const std::uint32_t zc = coarse.fitted();
                const auto cell = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) -> const SplitVoxel& {
                    return level.at(x, y, z);
                };
                coarse.rows.push_back(fitRow(coarse.dims, fitter, split::coarseInterior(), split::coarseOverlap(M), job,
                                             [&](std::uint32_t x, std::uint32_t y, float* w) {
                                                 split::fillCellWindow(cell, level.dims, M, x, y, zc, w);
                                             }));
                advance(l + 1);
            }
            if (coarse.fitted() < coarse.dims[2]) keepFrom = std::min(keepFrom, split::finerRows(coarse.fitted(), M, rowsAll)[0]);
        }
        level.dropBefore(keepFrom);
    };

    // Level 0, row by row, from a window of the volume's slices (as floats) that slides along z.
    std::deque<std::vector<float>> slices;
    std::uint32_t sliceBase = 0, sliceNext = 0;
    auto& finest = levels[0];
    for (std::uint32_t z = 0; z < finest.dims[2]; ++z) {
        const std::uint32_t need = std::min(d[2], (z + 1) * N + M);  // slices [.., need)
        while (sliceNext < need) {
            const std::uint32_t count = std::min<std::uint32_t>(16, d[2] - sliceNext);
            source.readSlices(sliceNext, count, slab.data());
            for (std::uint32_t s = 0; s < count; ++s) {
                std::vector<float> f(slice);
                for (std::size_t a = 0; a < slice; ++a) f[a] = storedValue(slab.data(), s * slice + a, g.scalarType);
                slices.push_back(std::move(f));
            }
            sliceNext += count;
            job.throwIfCancelled();
        }
        const auto voxel = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
            return slices[k - sliceBase][std::size_t(j) * d[0] + i];
        };
        finest.rows.push_back(fitRow(finest.dims, fitter, N, M, job, [&](std::uint32_t x, std::uint32_t y, float* w) {
            split::fillVoxelWindow(voxel, d, N, M, x, y, z, w);
        }));
        advance(0);
        // The next row's window starts M slices below its first voxel.
        const long keep = long(z + 1) * long(N) - long(M);
        while (!slices.empty() && long(sliceBase) < keep) {
            slices.pop_front();
            ++sliceBase;
        }
        job.report(0.1 + 0.9 * double(z + 1) / double(finest.dims[2]), "fitting split-voxels");
    }
    for (int l = 0; l < levelCount; ++l)
        if (levels[std::size_t(l)].nextBrickRow != rowNodes[std::size_t(l)].size())
            throw Error(output + ": the split-voxel build left level " + std::to_string(l) + " unwritten (a bug)");
    // A node's range covers its subtree: children follow their parents in the table.
    for (std::size_t id = nodes.size(); id-- > 1;) {
        auto& parent = nodes[nodes[id].parent];
        parent.minValue = std::min(parent.minValue, nodes[id].minValue);
        parent.maxValue = std::max(parent.maxValue, nodes[id].maxValue);
    }
    hvo::finishFile(header, nodes, out);

    BuildReport report;
    report.nodeCount = nodes.size();
    report.fileBytes = header.fileSize;
    report.inputBytes = g.byteSize();
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    job.report(1.0, "done");
    return report;
}

}  // namespace hvx::core
