#include "core/octree/SplitVoxelOctreeBuilder.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <vector>

#include "core/base/AtomicFileWriter.h"
#include "core/base/Error.h"
#include "core/octree/BrickCodec.h"
#include "core/octree/HvoHeader.h"
#include "core/octree/OctreeLayout.h"
#include "core/octree/SplitVoxelGrid.h"

namespace hvx::core {

SplitVoxelOctreeBuilder::SplitVoxelOctreeBuilder(BuildOptions build, SplitVoxelOptions split)
    : build_(std::move(build)), split_(split) {
    if (build_.brickSize < 4 || build_.brickSize > 256) throw Error("brick size must be between 4 and 256 cells");
    if (build_.lossy8) throw Error("split-voxels keep their values exactly: --lossy8 does not apply");
    if (build_.emptyBelow) throw Error("split-voxel octrees store every node: --empty-below does not apply");
    split_.validate();
}

BuildReport SplitVoxelOctreeBuilder::build(VoxelSource& source, const std::string& output, JobContext& job) {
    const auto t0 = std::chrono::steady_clock::now();
    const VolumeGeometry& g = source.geometry();
    g.validate(source.describe());
    if (g.voxelCount() > kMaxVoxels)
        throw Error(source.describe() + ": " + std::to_string(g.voxelCount()) +
                    " voxels; split-voxel builds hold the volume in memory for now and take up to " +
                    std::to_string(kMaxVoxels));
    SplitVoxelOptions split = split_;
    split.labels = split_.labels || build_.labels || g.isLabel;

    // The levels, finest first, to the one that fits a single brick.
    std::vector<SplitVoxelGrid> levels;
    {
        JobContext fitting(job, [&job](const JobProgress& p) { job.report(0.5 * p.fraction, "fitting split-voxels"); });
        levels.push_back(SplitVoxelGrid::build(source, split, fitting));
    }
    // The cell grid as a volume: what the layout, the header and every traversal see.
    VolumeGeometry cells = g;
    const double n = double(split.n);
    for (int a = 0; a < 3; ++a) {
        cells.dims[std::size_t(a)] = levels[0].dims()[std::size_t(a)];
        cells.spacing[a] = g.spacing[a] * n;
    }
    cells.origin = glm::dvec3(g.indexToPatient() * glm::dvec4(glm::dvec3((n - 1.0) / 2.0), 1.0));
    cells.isLabel = split.labels;
    const OctreeLayout layout(cells.dims, build_.brickSize);
    while (int(levels.size()) < layout.levelCount()) {
        JobContext coarsening(job, {});
        levels.push_back(levels.back().coarser(split, coarsening));
        job.report(0.5 + 0.3 * double(levels.size()) / double(layout.levelCount()), "coarser levels");
    }

    BuildOptions opt = build_;
    opt.border = 0;
    opt.labels = split.labels;
    hvo::FileHeader header = hvo::startHeader(cells, opt, layout.levelCount());
    header.version = hvo::kVersionSplitVoxels;
    header.flags = (header.flags & ~hvo::FileShuffled) | hvo::FileSplitVoxels;
    for (int a = 0; a < 3; ++a) header.split.sourceDims[a] = g.dims[std::size_t(a)];
    header.split.n = std::uint16_t(split.n);
    header.split.overlap = std::uint16_t(split.overlap);
    AtomicFileWriter out(output);
    out.append(&header, sizeof header);

    const std::size_t valueBytes = scalarSize(g.scalarType);
    const bool isSigned = g.scalarType == ScalarType::Int16;
    const std::size_t cellBytes = SplitVoxel::encodedSize(valueBytes);
    const std::uint32_t B = build_.brickSize;
    std::vector<hvo::NodeRecord> nodes = layout.nodes();
    std::vector<std::uint8_t> raw(std::size_t(B) * B * B * cellBytes);
    std::vector<std::byte> packed;
    for (std::size_t id = 0; id < nodes.size(); ++id) {
        job.throwIfCancelled();
        auto& rec = nodes[id];
        const SplitVoxelGrid& level = levels[rec.level];
        const auto& d = level.dims();
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        std::uint8_t* at = raw.data();
        for (std::uint32_t z = 0; z < B; ++z)
            for (std::uint32_t y = 0; y < B; ++y)
                for (std::uint32_t x = 0; x < B; ++x, at += cellBytes) {
                    // Cells past the grid repeat its last ones, as voxel bricks repeat their faces.
                    const SplitVoxel& v = level.at(std::min(rec.x * B + x, d[0] - 1), std::min(rec.y * B + y, d[1] - 1),
                                                   std::min(rec.z * B + z, d[2] - 1));
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
        job.report(0.8 + 0.2 * double(id) / double(nodes.size()), "writing bricks");
    }
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
