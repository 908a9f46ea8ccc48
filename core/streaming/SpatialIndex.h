#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace hvx::core {

class OctreeReader;

/// The current cut of the .hvo octree encoded for stackless ray casting (thesis §3.2.1): an
/// octree whose leaves are the cut's nodes (with a brick slot, or empty), stored as one
/// linearised array per attribute, with six neighbour links ("ropes") per node. The layout
/// and the traversal step are defined once in core/streaming/IndexTraversal.glsl.
///
/// Threading: a value type; build on one thread, read from many.
struct SpatialIndex {
    std::vector<glm::uvec4> nodes;      ///< see IndexTraversal.glsl
    std::vector<std::uint32_t> ropes;   ///< 6 per node
    std::vector<glm::vec2> ranges;      ///< min, max of the node's values
    /// Multilevel sampling (thesis §3.2.2, Fig. 3.6), per node, filled by linkParents(): x = the
    /// pool slot of a leaf's parent (kNone: no parent, not resident, or not linked); y = which of
    /// the leaf's eight corners (bit x + 2y + 4z, 1 = the high side) a coarser leaf with a brick
    /// touches. Empty until linked: every leaf samples its own level.
    std::vector<glm::uvec2> levels;
    /// How many leaves `levels` has blend with their parent (none: multilevel sampling draws
    /// what sampling each leaf's own level draws, and the ray casters skip it).
    std::size_t blendingLeaves = 0;
    /// Of those, how many touch a leaf two or more levels coarser: the blend reaches their
    /// parent's level there, not the neighbour's (a seam of one level remains).
    std::size_t steepLeaves = 0;

    static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
    static constexpr std::uint32_t kLeafBit = 0x100u;

    /// Builds the index of a cut. `cut` lists .hvo node ids forming the leaves; `slotOf(id)`
    /// gives each leaf's brick slot (kNone for an empty leaf). Regions outside the volume or not
    /// covered by the cut become empty leaves.
    template <class SlotOf>
    static SpatialIndex build(const OctreeReader& reader, const std::vector<std::uint32_t>& cut, SlotOf slotOf);
    /// Non-template core of build(): slots[i] belongs to cut[i].
    static SpatialIndex build(const OctreeReader& reader, const std::vector<std::uint32_t>& cut,
                              const std::vector<std::uint32_t>& slotIds);
    std::size_t leafCount() const;
    /// Fills `levels`: `slotOf(.hvo node id)` gives the pool slot holding a node's brick
    /// (kNone when none does). The working set keeps every refined node resident, so a cut leaf's
    /// parent has a slot.
    void linkParents(const OctreeReader& reader, const std::function<std::uint32_t(std::uint32_t)>& slotOf);
};

template <class SlotOf>
SpatialIndex SpatialIndex::build(const OctreeReader& reader, const std::vector<std::uint32_t>& cut, SlotOf slotOf) {
    std::vector<std::uint32_t> slotIds;  // not `slots`: a Qt macro where ui/ includes this header
    slotIds.reserve(cut.size());
    for (auto id : cut) slotIds.push_back(slotOf(id));
    return build(reader, cut, slotIds);
}

}  // namespace hvx::core
