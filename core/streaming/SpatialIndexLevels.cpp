// SpatialIndex::linkParents: what multilevel sampling needs of the cut (thesis §3.2.2, Fig. 3.6).
#include <algorithm>
#include <array>
#include <cmath>

#include "core/octree/OctreeReader.h"
#include "core/streaming/SpatialIndex.h"
#include "core/streaming/SpatialIndexTraversal.h"

namespace hvx::core {

bool SpatialIndex::LevelLink::operator==(const LevelLink& o) const {
    return std::equal(std::begin(ancestors), std::end(ancestors), std::begin(o.ancestors)) && blends == o.blends &&
           clamped == o.clamped && std::equal(std::begin(coarser), std::end(coarser), std::begin(o.coarser));
}

namespace {
/// A leaf with a brick: its box and depth, and the field's depth at its corners once known.
struct FieldLeaf {
    std::uint32_t node;
    std::uint32_t depth;
    glm::dvec3 lo;
    double size;
    std::array<double, 8> field{};  // the level field at the corners, as a depth (coarser: smaller)
};

/// Trilinear in a leaf's corner values at p (inside or on its box).
double fieldAt(const FieldLeaf& L, const glm::dvec3& p) {
    const glm::dvec3 u = glm::clamp((p - L.lo) / L.size, glm::dvec3(0.0), glm::dvec3(1.0));
    double f = 0.0;
    for (std::uint32_t c = 0; c < 8; ++c)
        f += L.field[c] * ((c & 1u) ? u.x : 1.0 - u.x) * ((c & 2u) ? u.y : 1.0 - u.y) * ((c & 4u) ? u.z : 1.0 - u.z);
    return f;
}
}  // namespace

void SpatialIndex::linkParents(const OctreeReader& reader, const std::function<std::uint32_t(std::uint32_t)>& slotOf) {
    levels.assign(nodes.size(), LevelLink{});
    blendingLeaves = 0;
    steepLeaves = 0;
    levelReach = 0;
    const auto& hn = reader.nodes();
    const int top = int(reader.levelCount()) - 1;
    std::vector<FieldLeaf> leaves;
    std::vector<std::uint32_t> leafOf(nodes.size(), kNone);  // index node -> entry of `leaves`
    for (std::uint32_t i = 0; i < nodes.size(); ++i) {
        const auto& nd = nodes[i];
        if (!(nd.y & kLeafBit) || nd.x == kNone || nd.z == kNone) continue;
        const auto& h = hn[nd.z];
        const double size = std::ldexp(1.0, -(top - int(h.level)));
        leaves.push_back({i, nd.y & 0xFFu, glm::dvec3(h.x, h.y, h.z) * size, size});
    }
    // Coarse to fine: a corner's field comes from a strictly coarser leaf or is the leaf's own level.
    std::stable_sort(leaves.begin(), leaves.end(), [](const FieldLeaf& a, const FieldLeaf& b) { return a.depth < b.depth; });
    for (std::uint32_t k = 0; k < leaves.size(); ++k) leafOf[leaves[k].node] = k;
    for (auto& L : leaves) {
        // The leaves holding the centres of the 26 cubes of this leaf's size around it (and
        // itself): any leaf as coarse as this one or coarser that touches a corner covers a whole
        // such cube beside it (leaves are aligned cubes of power-of-two sizes). Inside the
        // volume only: outside it there are no leaves.
        std::array<const FieldLeaf*, 27> around{};
        for (int k = 0; k < 27; ++k) {
            const glm::ivec3 o(k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1);
            if (o == glm::ivec3(0)) {
                around[std::size_t(k)] = &L;
                continue;
            }
            const glm::dvec3 centre = L.lo + L.size * (glm::dvec3(o) + 0.5);
            if (centre.x < 0 || centre.y < 0 || centre.z < 0 || centre.x >= 1 || centre.y >= 1 || centre.z >= 1) continue;
            std::uint32_t j = 0;  // the leaf holding it (the traversal's own descent)
            glm::vec3 boxLo(0.0f), boxHi(1.0f);
            glsl::hvxDescend(*this, j, boxLo, boxHi, glm::vec3(centre));
            if (leafOf[j] != kNone) around[std::size_t(k)] = &leaves[leafOf[j]];
        }
        for (std::uint32_t c = 0; c < 8; ++c) {
            const glm::ivec3 side(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u);
            // The coarsest leaf with a brick touching the corner, among the eight cubes around it.
            const FieldLeaf* coarsest = &L;
            for (std::uint32_t o = 0; o < 8; ++o) {
                const glm::ivec3 cube = side + glm::ivec3(o & 1u, (o >> 1) & 1u, (o >> 2) & 1u);  // 0..2 per axis
                const FieldLeaf* other = around[std::size_t(cube.x + 3 * cube.y + 9 * cube.z)];
                if (other && other->depth < coarsest->depth) coarsest = other;
            }
            // Its field there: its own level at its own corner, interpolated at a hanging one
            // (already known: coarser leaves come first).
            const glm::dvec3 corner = L.lo + L.size * glm::dvec3(side);
            L.field[c] = coarsest == &L ? double(L.depth) : fieldAt(*coarsest, corner);
        }
    }
    for (const auto& L : leaves) {
        const auto& h = hn[nodes[L.node].z];
        if (h.parent == hvo::kNoNode) continue;
        LevelLink& link = levels[L.node];
        link.ancestors[0] = slotOf(h.parent);
        if (link.ancestors[0] == kNone) continue;
        double reach = 0.0;
        for (std::uint32_t c = 0; c < 8; ++c) reach = std::max(reach, double(L.depth) - L.field[c]);
        if (reach <= 0.0) continue;
        // The ancestors the field reaches (ancestors[k], k + 1 levels up, where f passes k), as far as they are resident.
        const auto needed = std::uint32_t(std::ceil(std::min(reach, double(kLevelSpan))));
        double span = double(needed);
        auto up = h.parent;
        for (std::uint32_t k = 1; k < needed; ++k) {
            up = hn[up].parent;
            link.ancestors[k] = up == hvo::kNoNode ? kNone : slotOf(up);
            if (link.ancestors[k] == kNone) {
                span = double(k);
                break;
            }
        }
        for (std::uint32_t c = 0; c < 8; ++c) {
            link.coarser[c] = float(std::min(double(L.depth) - L.field[c], span));
            levelReach = std::max(levelReach, std::uint32_t(std::ceil(link.coarser[c])));
        }
        link.blends = 1;
        ++blendingLeaves;
        link.clamped = reach > span ? 1u : 0u;
        steepLeaves += link.clamped;
    }
}

}  // namespace hvx::core
