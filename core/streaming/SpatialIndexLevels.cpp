// SpatialIndex::linkParents: what multilevel sampling needs of the cut (thesis §3.2.2, Fig. 3.6).
#include <array>
#include <cmath>

#include "core/octree/OctreeReader.h"
#include "core/streaming/SpatialIndex.h"
#include "core/streaming/SpatialIndexTraversal.h"

namespace hvx::core {

namespace {
/// The 26 cubes of a leaf's size around it, each with the leaf's corners it shares (bit x + 2y +
/// 4z, 1 = the high side): offset −1 on an axis shares the low corners, +1 the high ones, 0 both.
struct Neighbour {
    glm::ivec3 offset;
    std::uint32_t corners;
};
constexpr std::array<Neighbour, 26> neighbours() {
    std::array<Neighbour, 26> out{};
    std::size_t k = 0;
    for (int z = -1; z <= 1; ++z)
        for (int y = -1; y <= 1; ++y)
            for (int x = -1; x <= 1; ++x) {
                if (x == 0 && y == 0 && z == 0) continue;
                std::uint32_t mask = 0;
                for (std::uint32_t c = 0; c < 8; ++c) {
                    const int cx = int(c & 1u), cy = int((c >> 1) & 1u), cz = int((c >> 2) & 1u);
                    auto shares = [](int d, int side) { return d == 0 || (d < 0 ? side == 0 : side == 1); };
                    if (shares(x, cx) && shares(y, cy) && shares(z, cz)) mask |= 1u << c;
                }
                out[k++] = {glm::ivec3(x, y, z), mask};
            }
    return out;
}
constexpr auto kNeighbours = neighbours();
}  // namespace

void SpatialIndex::linkParents(const OctreeReader& reader, const std::function<std::uint32_t(std::uint32_t)>& slotOf) {
    levels.assign(nodes.size(), glm::uvec2(kNone, 0u));
    blendingLeaves = 0;
    steepLeaves = 0;
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
        // A coarser leaf touching a corner covers the whole cube of this leaf's size beside it
        // (leaves are aligned cubes of power-of-two sizes), so the leaf holding that cube's centre
        // is it; a leaf as fine or finer there means no coarser one touches that side. Corners
        // within the volume only: outside it there are no leaves.
        std::uint32_t corners = 0;
        bool steep = false;
        for (const auto& nb : kNeighbours) {
            if ((corners & nb.corners) == nb.corners && steep) continue;
            const glm::dvec3 centre = lo + size * (glm::dvec3(nb.offset) + 0.5);
            if (centre.x < 0 || centre.y < 0 || centre.z < 0 || centre.x >= 1 || centre.y >= 1 || centre.z >= 1) continue;
            std::uint32_t j = 0;  // the leaf holding it (the traversal's own descent)
            glm::vec3 boxLo(0.0f), boxHi(1.0f);
            glsl::hvxDescend(*this, j, boxLo, boxHi, glm::vec3(centre));
            if (nodes[j].x != kNone && (nodes[j].y & 0xFFu) < depth) {
                corners |= nb.corners;
                steep = steep || (nodes[j].y & 0xFFu) + 1 < depth;
            }
        }
        levels[i] = glm::uvec2(parentSlot, corners);
        blendingLeaves += corners != 0u;
        steepLeaves += steep;
    }
}

}  // namespace hvx::core
