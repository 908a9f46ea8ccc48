#include "core/streaming/SpatialIndex.h"

#include <unordered_map>

#include "core/octree/OctreeReader.h"

namespace hvx::core {

SpatialIndex SpatialIndex::build(const OctreeReader& reader, const std::vector<std::uint32_t>& cut,
                                 const std::vector<std::uint32_t>& slots) {
    std::unordered_map<std::uint32_t, std::uint32_t> inCut;
    for (std::size_t i = 0; i < cut.size(); ++i) inCut[cut[i]] = slots[i];
    // Ancestors of cut nodes are inner index nodes.
    std::vector<char> inner(reader.nodes().size(), 0);
    for (auto id : cut)
        for (auto p = reader.nodes()[id].parent; p != hvo::kNoNode; p = reader.nodes()[p].parent) {
            if (inner[p]) break;
            inner[p] = 1;
        }
    SpatialIndex idx;
    const auto& hn = reader.nodes();
    auto addLeaf = [&](std::uint32_t depth, std::uint32_t hvoId, std::uint32_t slot, std::uint32_t parent) {
        idx.nodes.push_back(glm::uvec4(slot, depth | kLeafBit, hvoId, parent));
        if (hvoId != kNone) idx.ranges.push_back(glm::vec2(hn[hvoId].minValue, hn[hvoId].maxValue));
        else idx.ranges.push_back(glm::vec2(0.0f));
    };
    // Breadth first; index node i <-> .hvo node ids[i].
    std::vector<std::uint32_t> ids;
    if (inCut.count(0)) addLeaf(0, 0, inCut[0], kNone);
    else if (inner[0]) {
        idx.nodes.push_back(glm::uvec4(0, 0, 0, kNone));
        idx.ranges.push_back(glm::vec2(hn[0].minValue, hn[0].maxValue));
    } else addLeaf(0, 0, kNone, kNone);
    ids.push_back(0);
    for (std::size_t i = 0; i < idx.nodes.size(); ++i) {
        if (idx.nodes[i].y & kLeafBit) continue;
        const std::uint32_t h = ids[i];
        const std::uint32_t depth = (idx.nodes[i].y & 0xFFu) + 1;
        idx.nodes[i].x = std::uint32_t(idx.nodes.size());
        const auto& node = hn[h];
        std::uint32_t c = node.firstChild;
        for (std::uint32_t o = 0; o < 8; ++o) {
            std::uint32_t child = kNone;
            if (node.childMask & (1u << o)) child = c++;
            if (child != kNone && inner[child] && !inCut.count(child)) {
                idx.nodes.push_back(glm::uvec4(0, depth, child, std::uint32_t(i)));
                idx.ranges.push_back(glm::vec2(hn[child].minValue, hn[child].maxValue));
            } else {
                addLeaf(depth, child, child != kNone && inCut.count(child) ? inCut[child] : kNone, std::uint32_t(i));
            }
            ids.push_back(child);
        }
    }
    // Ropes, top down: siblings inside the parent, else the parent's rope, refined one level
    // down when that neighbour has children (equal level), else kept coarser.
    idx.ropes.assign(idx.nodes.size() * 6, kNone);
    for (std::size_t i = 0; i < idx.nodes.size(); ++i) {
        if (idx.nodes[i].y & kLeafBit) continue;
        const std::uint32_t first = idx.nodes[i].x;
        for (std::uint32_t o = 0; o < 8; ++o) {
            const std::uint32_t child = first + o;
            for (int axis = 0; axis < 3; ++axis) {
                const std::uint32_t bit = 1u << axis;
                const bool high = (o & bit) != 0;
                // Inner face: the sibling across it.
                idx.ropes[child * 6 + std::uint32_t(2 * axis + (high ? 0 : 1))] = first + (o ^ bit);
                // Outer face: via the parent's neighbour.
                const int face = 2 * axis + (high ? 1 : 0);
                std::uint32_t r = idx.ropes[i * 6 + std::size_t(face)];
                if (r != kNone && !(idx.nodes[r].y & kLeafBit)) r = idx.nodes[r].x + (o ^ bit);
                idx.ropes[child * 6 + std::uint32_t(face)] = r;
            }
        }
    }
    return idx;
}

std::size_t SpatialIndex::leafCount() const {
    std::size_t n = 0;
    for (const auto& nd : nodes) n += (nd.y & kLeafBit) != 0;
    return n;
}

}  // namespace hvx::core
