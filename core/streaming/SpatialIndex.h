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
    static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
    static constexpr std::uint32_t kLeafBit = 0x100u;

    std::vector<glm::uvec4> nodes;      ///< see IndexTraversal.glsl
    std::vector<std::uint32_t> ropes;   ///< 6 per node
    std::vector<glm::vec2> ranges;      ///< min, max of the node's values
    /// Multilevel sampling (thesis §3.2.2, Fig. 3.6): where a leaf samples which level. The cut
    /// defines a continuous level field over the volume: at a corner of leaves, the level of the
    /// coarsest leaf with a brick touching it, or, where that corner lies inside a face or an
    /// edge of the coarsest leaf, that leaf's field there (a hanging corner); trilinear inside
    /// each leaf. So two leaves sharing a face see the same field on it, whatever their levels. A
    /// sample where the field is f levels coarser than the leaf blends the two levels around it
    /// (quadrilinear): the leaf's own with its parent's for f <= 1, the k-th ancestor's with the
    /// (k+1)-th's for k < f <= k + 1, up to f = kLevelSpan (every octree of up to kLevelSpan + 2
    /// levels: 4096³ voxels in bricks of 32). Laid out as std430 for the shader (binding 12).
    static constexpr std::uint32_t kLevelSpan = 6;
    struct LevelLink {
        /// The pool slots of the leaf's parent (0), grandparent (1) and on, as far as the field
        /// reaches (kNone past it; the parent's kNone: none, not resident or not linked).
        std::uint32_t ancestors[kLevelSpan] = {kNone, kNone, kNone, kNone, kNone, kNone};
        std::uint32_t blends = 0;   ///< 1 where the field is coarser than the leaf somewhere
        std::uint32_t clamped = 0;  ///< 1 where the field reaches further than the leaf samples (steepLeaves)
        float coarser[8] = {};  ///< per corner (x + 2y + 4z, 1 = the high side): how many levels coarser the field is
        bool operator==(const LevelLink& o) const;
    };
    /// Per node, filled by linkParents(); empty until linked: every leaf samples its own level.
    std::vector<LevelLink> levels;
    /// How many leaves blend (none: multilevel sampling draws what sampling each leaf's own
    /// level draws, and the ray casters skip it).
    std::size_t blendingLeaves = 0;
    /// How many levels up the field reaches anywhere in the cut (the largest corner value, rounded
    /// up): the ray casters' variant carries only the ancestors' code it needs.
    std::uint32_t levelReach = 0;
    /// Of those, how many the field reaches further than they can follow (more than kLevelSpan
    /// levels coarser, or an ancestor not resident): clamped there, a seam remains.
    std::size_t steepLeaves = 0;

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
    /// ancestors have slots.
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
