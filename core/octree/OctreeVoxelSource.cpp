#include "core/octree/OctreeVoxelSource.h"

#include <cstring>

#include "core/base/Error.h"

namespace hvx::core {

OctreeVoxelSource::OctreeVoxelSource(std::shared_ptr<const OctreeReader> reader)
    : reader_(std::move(reader)), layout_(reader_->geometry().dims, reader_->brickSize()) {
    if (reader_->splitVoxels())
        throw Error(reader_->path() + " is a split-voxel octree: its cells are not the volume's voxels");
    for (const auto& n : reader_->nodes())
        if (n.level == 0 && (n.flags & hvo::NodeLossy8))
            throw Error(reader_->path() + " stores its bricks lossily (8-bit): its values are not the volume's; "
                        "build from the volume's own files");
    if (layout_.nodes().size() != reader_->nodes().size())
        throw Error(reader_->path() + ": its node table does not match its dimensions and brick size");
}

std::vector<std::string> OctreeVoxelSource::warnings() const {
    const auto& h = reader_->header();
    if (!(h.flags & hvo::FileEmptyThreshold)) return {};
    return {reader_->path() + " was built with an empty threshold (stored value " + std::to_string(h.emptyBelow) +
            "): its bricks wholly below it read back as their smallest value, not voxel by voxel"};
}

void OctreeVoxelSource::loadRow(std::uint32_t row) {
    if (row == row_) return;
    const auto& grid = layout_.levelNodes(0);
    bricks_.clear();
    bricks_.reserve(std::size_t(grid[0]) * grid[1]);
    for (std::uint32_t y = 0; y < grid[1]; ++y)
        for (std::uint32_t x = 0; x < grid[0]; ++x) bricks_.push_back(reader_->readBrick(layout_.nodeId(0, x, y, row)));
    row_ = row;
}

void OctreeVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const auto& g = reader_->geometry();
    const auto& dims = g.dims;
    if (std::uint64_t(firstSlice) + count > dims[2])
        throw Error(reader_->path() + ": slices " + std::to_string(firstSlice) + " to " +
                    std::to_string(std::uint64_t(firstSlice) + count) + " lie outside its " + std::to_string(dims[2]));
    const std::uint32_t B = reader_->brickSize(), border = reader_->border(), edge = reader_->brickEdge();
    const std::size_t bytes = scalarSize(g.scalarType);
    const auto& grid = layout_.levelNodes(0);
    auto* out = static_cast<unsigned char*>(dst);
    for (std::uint32_t s = 0; s < count; ++s) {
        const std::uint32_t k = firstSlice + s;
        loadRow(k / B);
        const std::uint32_t bz = k % B + border;
        for (std::uint32_t j = 0; j < dims[1]; ++j) {
            const std::uint32_t by = j % B + border;
            for (std::uint32_t nx = 0; nx < grid[0]; ++nx) {
                const Brick& b = bricks_[std::size_t(j / B) * grid[0] + nx];
                const std::uint32_t i0 = nx * B, n = std::min(B, dims[0] - i0);
                const std::size_t from = ((std::size_t(bz) * edge + by) * edge + border) * bytes;
                std::memcpy(out + ((std::size_t(s) * dims[1] + j) * dims[0] + i0) * bytes,
                            reinterpret_cast<const unsigned char*>(b.data.data()) + from, n * bytes);
            }
        }
    }
}

}  // namespace hvx::core
