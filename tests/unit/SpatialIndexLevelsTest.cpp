// SpatialIndex::linkParents (multilevel sampling, thesis §3.2.2): each leaf with a brick gets its
// parent's slot and the corners a coarser leaf with a brick touches. Checked against the
// definition by brute force — every pair of leaves, each corner tested against every other
// leaf's closed box — on random cuts with random empty leaves and parents missing from the pool.
// The working set builds and links the index anew only when the cut or a slot changes.
#include <gtest/gtest.h>

#include <random>
#include <tuple>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/SpatialIndex.h"
#include "core/streaming/WorkingSet.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/RandomCut.h"
#include "tests/support/TempDir.h"

using namespace hvx;

namespace {
struct Box {
    glm::dvec3 lo, hi;
};

/// Every index leaf's box, by walking the index from its root.
std::vector<Box> leafBoxes(const core::SpatialIndex& idx) {
    std::vector<Box> boxes(idx.nodes.size(), {glm::dvec3(-1.0), glm::dvec3(-1.0)});
    std::vector<std::tuple<std::uint32_t, glm::dvec3, glm::dvec3>> stack{{0u, glm::dvec3(0.0), glm::dvec3(1.0)}};
    while (!stack.empty()) {
        const auto [n, lo, hi] = stack.back();
        stack.pop_back();
        const auto& nd = idx.nodes[n];
        if (nd.y & core::SpatialIndex::kLeafBit) {
            boxes[n] = {lo, hi};
            continue;
        }
        const glm::dvec3 mid = 0.5 * (lo + hi);
        for (std::uint32_t oct = 0; oct < 8; ++oct) {
            const glm::dvec3 s((oct & 1) ? 1 : 0, (oct & 2) ? 1 : 0, (oct & 4) ? 1 : 0);
            stack.push_back({nd.x + oct, glm::mix(lo, mid, s), glm::mix(mid, hi, s)});
        }
    }
    return boxes;
}

bool contains(const Box& b, const glm::dvec3& p) {
    const double e = 1e-12;
    return p.x >= b.lo.x - e && p.y >= b.lo.y - e && p.z >= b.lo.z - e && p.x <= b.hi.x + e && p.y <= b.hi.y + e &&
           p.z <= b.hi.z + e;
}

/// A pool that holds some nodes and not others (deterministic per id).
std::uint32_t slotOf(std::uint32_t id, std::uint32_t seed) {
    return ((id + seed) * 2654435761u >> 9) % 7 == 0 ? core::SpatialIndex::kNone : id + 1;
}
}  // namespace

TEST(SpatialIndexLevels, ACornerIsMarkedExactlyWhereACoarserLeafWithABrickTouchesIt) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({70, 52, 45});
    core::BuildOptions options;
    options.brickSize = 4;  // five levels
    core::JobContext job;
    core::OctreeBuilder(options).build(phantom, dir.file("p.hvo"), job);
    const auto reader = core::OctreeReader::open(dir.file("p.hvo"));
    ASSERT_GE(reader->levelCount(), 4u);
    std::mt19937 rng(21);
    std::size_t linked = 0, blending = 0, marked = 0, steepTotal = 0;
    for (std::uint32_t trial = 0; trial < 12; ++trial) {
        const auto cut = test::randomCut(*reader, rng, 0.55 + 0.03 * trial);
        std::vector<std::uint32_t> slots;
        for (auto id : cut) slots.push_back(slotOf(id, trial));
        auto idx = core::SpatialIndex::build(*reader, cut, slots);
        idx.linkParents(*reader, [&](std::uint32_t id) { return slotOf(id, trial); });
        ASSERT_EQ(idx.levels.size(), idx.nodes.size());
        const auto boxes = leafBoxes(idx);
        std::size_t blendingHere = 0, steepHere = 0;
        for (std::size_t i = 0; i < idx.nodes.size(); ++i) {
            const auto& nd = idx.nodes[i];
            const bool leaf = nd.y & core::SpatialIndex::kLeafBit;
            const bool withParent = leaf && nd.x != core::SpatialIndex::kNone && nd.z != core::SpatialIndex::kNone &&
                                    reader->nodes()[nd.z].parent != core::hvo::kNoNode &&
                                    slotOf(reader->nodes()[nd.z].parent, trial) != core::SpatialIndex::kNone;
            if (!withParent) {
                EXPECT_EQ(idx.levels[i], glm::uvec2(core::SpatialIndex::kNone, 0u)) << "node " << i;
                continue;
            }
            ++linked;
            EXPECT_EQ(idx.levels[i].x, slotOf(reader->nodes()[nd.z].parent, trial));
            std::uint32_t want = 0;
            bool steep = false;
            for (std::uint32_t c = 0; c < 8; ++c) {
                const glm::dvec3 corner = glm::mix(boxes[i].lo, boxes[i].hi, glm::dvec3(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u));
                for (std::size_t j = 0; j < idx.nodes.size(); ++j) {
                    const auto& other = idx.nodes[j];
                    if (!(other.y & core::SpatialIndex::kLeafBit) || other.x == core::SpatialIndex::kNone) continue;
                    if ((other.y & 0xFFu) < (nd.y & 0xFFu) && contains(boxes[j], corner)) {
                        want |= 1u << c;
                        steep = steep || (other.y & 0xFFu) + 1 < (nd.y & 0xFFu);
                    }
                }
            }
            EXPECT_EQ(idx.levels[i].y, want) << "trial " << trial << ", leaf " << i;
            blendingHere += want != 0u;
            steepHere += steep;
            marked += std::uint32_t(__builtin_popcount(want));
        }
        EXPECT_EQ(idx.blendingLeaves, blendingHere);
        EXPECT_EQ(idx.steepLeaves, steepHere);
        blending += blendingHere;
        steepTotal += steepHere;
    }
    std::printf("%zu leaves linked to their parents, %zu of them blending (%zu beside a leaf two or more levels coarser), "
                "%zu corners marked\n",
                linked, blending, steepTotal, marked);
    EXPECT_GT(steepTotal, 10u);
    EXPECT_GT(blending, 100u);  // the cuts mix levels: the check has corners to find
    EXPECT_GT(linked, blending);  // and leaves with none
}

TEST(SpatialIndexLevels, TheWorkingSetRebuildsTheIndexOnlyWhenTheCutOrASlotChanges) {
    test::TempDir dir;
    core::PhantomVoxelSource phantom({96, 96, 80});
    core::BuildOptions options;
    options.brickSize = 8;
    core::JobContext job;
    core::OctreeBuilder(options).build(phantom, dir.file("p.hvo"), job);
    const auto reader = core::OctreeReader::open(dir.file("p.hvo"));
    const auto& g = reader->geometry();
    const auto tf = core::TransferFunction::preset("ct-bone", g.valueMin, g.valueMax, 1.0, 0.0, 1.0);
    core::BrickCache cache(1u << 28);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSet ws(*reader, cache, loader, core::WorkingSetOptions{});
    const auto centre = ws.space().centre();
    const auto far = core::View::orbit(centre, 4000.0, 0.0, 0.0, 32, 32), near = core::View::orbit(centre, 1200.0, 0.0, 0.0, 256, 256);
    ws.converge({far}, tf);
    const auto before = ws.index();
    const std::size_t farCut = ws.stats().cutNodes;
    ws.update({far}, tf);  // the same view: the same cut
    EXPECT_FALSE(ws.stats().indexRebuilt);
    EXPECT_EQ(ws.stats().levelsMs, 0.0);
    EXPECT_EQ(ws.index().nodes, before.nodes);
    EXPECT_EQ(ws.index().levels, before.levels);
    ws.converge({near}, tf);  // a larger image: a finer cut
    std::printf("cut of %zu nodes far, %zu near\n", farCut, ws.stats().cutNodes);
    EXPECT_GT(ws.stats().cutNodes, farCut);
    EXPECT_NE(ws.index().nodes, before.nodes);
    // What the working set keeps is what building and linking the cut afresh gives.
    std::vector<std::uint32_t> slots;
    for (auto id : ws.cut()) {
        std::uint32_t slot = core::SpatialIndex::kNone;
        for (std::size_t i = 0; i < ws.index().nodes.size(); ++i)
            if (ws.index().nodes[i].z == id && (ws.index().nodes[i].y & core::SpatialIndex::kLeafBit)) slot = ws.index().nodes[i].x;
        slots.push_back(slot);
    }
    const auto fresh = core::SpatialIndex::build(*reader, ws.cut(), slots);
    EXPECT_EQ(ws.index().nodes, fresh.nodes);
    EXPECT_EQ(ws.index().ropes, fresh.ropes);
    ws.update({near}, tf);
    EXPECT_FALSE(ws.stats().indexRebuilt) << "a settled cut was built again";
}
