#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/octree/HvoFormat.h"

namespace hvx::core {

/// The branch-on-need node structure of an octree over a volume: how many levels, how many
/// nodes per level, and the breadth-first node numbering the .hvo file uses. It depends only on
/// the volume dimensions and the brick size, so builder and reader derive the same layout.
class OctreeLayout {
public:
    using Dims = std::array<std::uint32_t, 3>;
    /// Computes the layout; brickSize must be >= 1.
    OctreeLayout(Dims volumeDims, std::uint32_t brickSize);

    /// The node and level counts a volume of `volumeDims` in bricks of `brickSize` has, worked
    /// out without building anything (so a hostile header cannot make a reader allocate);
    /// nodes is UINT64_MAX when it would exceed 2^32 or need more than 65535 bricks per axis.
    struct Counts {
        std::uint64_t nodes = 0;
        int levels = 0;
    };
    static Counts count(Dims volumeDims, std::uint32_t brickSize);
    int levelCount() const { return int(levelDims_.size()); }
    std::uint32_t brickSize() const { return brickSize_; }
    /// Voxel dimensions of the volume at `level` (level 0 = full resolution).
    const Dims& levelDims(int level) const { return levelDims_[std::size_t(level)]; }
    /// Node grid dimensions at `level`.
    const Dims& levelNodes(int level) const { return levelNodes_[std::size_t(level)]; }
    /// Node records with structure fields filled (coordinates, level, parent, children);
    /// payload fields are zero.
    const std::vector<hvo::NodeRecord>& nodes() const { return nodes_; }
    /// Id of the node at grid coordinate (x, y, z) of `level`.
    std::uint32_t nodeId(int level, std::uint32_t x, std::uint32_t y, std::uint32_t z) const;

private:
    std::uint32_t brickSize_;
    std::vector<Dims> levelDims_;
    std::vector<Dims> levelNodes_;
    std::vector<std::vector<std::uint32_t>> gridToId_;
    std::vector<hvo::NodeRecord> nodes_;
};

}  // namespace hvx::core
