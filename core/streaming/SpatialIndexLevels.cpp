// SpatialIndex::linkParents: what multilevel sampling needs of the cut (thesis §3.2.2, Fig. 3.6).
#include <cmath>

#include "core/octree/OctreeReader.h"
#include "core/streaming/SpatialIndex.h"
#include "core/streaming/SpatialIndexTraversal.h"

namespace hvx::core {

void SpatialIndex::linkParents(const OctreeReader& reader, const std::function<std::uint32_t(std::uint32_t)>& slotOf) {
    levels.assign(nodes.size(), glm::uvec2(kNone, 0u));
    blendingLeaves = 0;
    const auto& hn = reader.nodes();
    const int top = int(reader.levelCount()) - 1;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const auto& nd = nodes[i];
        if (!(nd.y & kLeafBit) || nd.x == kNone || nd.z == kNone) continue;
        const auto& h = hn[nd.z];
        if (h.parent == hvo::kNoNode) continue;
        const std::uint32_t parentSlot = slotOf(h.parent);
        if (parentSlot == kNone) continue;
        const std::uint32_t depth = nd.y & 0xFFu;
        const double size = std::ldexp(1.0, -(top - int(h.level)));
        const glm::dvec3 lo = glm::dvec3(h.x, h.y, h.z) * size;
        // A corner is touched by the (up to) eight leaves around it: those a point a little way
        // off the corner towards each octant falls in.
        const double off = size * 1e-3;
        std::uint32_t corners = 0;
        for (std::uint32_t c = 0; c < 8; ++c) {
            const glm::dvec3 corner = lo + size * glm::dvec3(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u);
            for (std::uint32_t o = 0; o < 8 && !(corners & (1u << c)); ++o) {
                const glm::dvec3 q = corner + off * glm::dvec3(o & 1u ? 1 : -1, o & 2u ? 1 : -1, o & 4u ? 1 : -1);
                if (q.x < 0 || q.y < 0 || q.z < 0 || q.x >= 1 || q.y >= 1 || q.z >= 1) continue;
                std::uint32_t j = 0;  // the leaf holding q (the traversal's own descent)
                glm::vec3 boxLo(0.0f), boxHi(1.0f);
                glsl::hvxDescend(*this, j, boxLo, boxHi, glm::vec3(q));
                if (j != i && nodes[j].x != kNone && (nodes[j].y & 0xFFu) < depth) corners |= 1u << c;
            }
        }
        levels[i] = glm::uvec2(parentSlot, corners);
        blendingLeaves += corners != 0u;
    }
}

}  // namespace hvx::core
