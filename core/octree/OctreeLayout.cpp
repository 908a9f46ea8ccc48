#include "core/octree/OctreeLayout.h"

#include <cstring>
#include <limits>

#include "core/base/Error.h"

namespace hvx::core {

OctreeLayout::OctreeLayout(Dims volumeDims, std::uint32_t brickSize) : brickSize_(brickSize) {
    if (brickSize == 0) throw Error("brick size must be at least 1");
    Dims d = volumeDims;
    for (;;) {
        Dims n{};
        for (int a = 0; a < 3; ++a) n[a] = (d[a] + brickSize - 1) / brickSize;
        if (n[0] > 65535 || n[1] > 65535 || n[2] > 65535) throw Error("volume needs more than 65535 bricks along an axis");
        levelDims_.push_back(d);
        levelNodes_.push_back(n);
        if (n[0] == 1 && n[1] == 1 && n[2] == 1) break;
        for (int a = 0; a < 3; ++a) d[a] = (d[a] + 1) / 2;
        if (levelDims_.size() > 32) throw Error("octree would need more than 32 levels");
    }
    const int top = levelCount() - 1;
    gridToId_.resize(levelDims_.size());
    for (std::size_t l = 0; l < levelNodes_.size(); ++l) {
        const auto& n = levelNodes_[l];
        gridToId_[l].assign(std::size_t(n[0]) * n[1] * n[2], hvo::kNoNode);
    }
    hvo::NodeRecord root{};
    root.parent = hvo::kNoNode;
    root.firstChild = hvo::kNoNode;
    root.level = std::uint8_t(top);
    nodes_.push_back(root);
    gridToId_[std::size_t(top)][0] = 0;
    // Breadth first: children of node i are appended as a contiguous run, in octant order.
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const int level = nodes_[i].level;
        if (level == 0) continue;
        const auto& cn = levelNodes_[std::size_t(level - 1)];
        std::uint8_t mask = 0;
        const auto first = std::uint32_t(nodes_.size());
        for (std::uint32_t o = 0; o < 8; ++o) {
            const std::uint32_t cx = 2u * nodes_[i].x + (o & 1u), cy = 2u * nodes_[i].y + ((o >> 1) & 1u),
                                cz = 2u * nodes_[i].z + ((o >> 2) & 1u);
            if (cx >= cn[0] || cy >= cn[1] || cz >= cn[2]) continue;
            hvo::NodeRecord c{};
            c.parent = std::uint32_t(i);
            c.firstChild = hvo::kNoNode;
            c.x = std::uint16_t(cx);
            c.y = std::uint16_t(cy);
            c.z = std::uint16_t(cz);
            c.level = std::uint8_t(level - 1);
            gridToId_[std::size_t(level - 1)][(std::size_t(cz) * cn[1] + cy) * cn[0] + cx] = std::uint32_t(nodes_.size());
            nodes_.push_back(c);
            mask = std::uint8_t(mask | (1u << o));
        }
        nodes_[i].childMask = mask;
        nodes_[i].firstChild = mask ? first : hvo::kNoNode;
        if (nodes_.size() >= std::numeric_limits<std::uint32_t>::max()) throw Error("octree has too many nodes");
    }
}

OctreeLayout::Counts OctreeLayout::count(Dims d, std::uint32_t brickSize) {
    Counts c;
    if (brickSize == 0) return {UINT64_MAX, 0};
    for (;;) {
        std::uint64_t level = 1;
        bool single = true;
        for (int a = 0; a < 3; ++a) {
            const std::uint64_t n = (std::uint64_t(d[a]) + brickSize - 1) / brickSize;
            if (n > 65535) return {UINT64_MAX, c.levels};
            level *= n;  // at most 65535^3 < 2^48
            single = single && n == 1;
        }
        c.nodes += level;
        ++c.levels;
        if (c.nodes > (1ull << 32)) return {UINT64_MAX, c.levels};
        if (single) return c;
        if (c.levels > 32) return {UINT64_MAX, c.levels};
        for (int a = 0; a < 3; ++a) d[a] = (d[a] + 1) / 2;
    }
}

std::uint32_t OctreeLayout::nodeId(int level, std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    if (level < 0 || level >= levelCount()) return hvo::kNoNode;
    const auto& n = levelNodes_[std::size_t(level)];
    if (x >= n[0] || y >= n[1] || z >= n[2]) return hvo::kNoNode;
    return gridToId_[std::size_t(level)][(std::size_t(z) * n[1] + y) * n[0] + x];
}

}  // namespace hvx::core
