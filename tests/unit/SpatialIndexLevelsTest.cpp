// SpatialIndex::linkParents (multilevel sampling, thesis §3.2.2): each leaf with a brick gets its
// ancestors' slots, as far up as the level field reaches, and the field at its corners. Checked
// by brute force on random cuts with random empty leaves and parents missing from the pool: the
// field is coarser than a leaf exactly at the corners a coarser leaf with a brick touches (every
// pair of leaves, each corner against every other leaf's closed box); and, with every node
// resident, two leaves sharing a face see the same field on it, at any pair of levels. The
// working set builds and links the index anew only when the cut, a slot or an ancestor's slot
// changes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
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
/// The level field a leaf sees at p (a depth: coarser is smaller), from its corners.
double fieldFrom(const core::SpatialIndex& idx, std::size_t leaf, const Box& box, const glm::dvec3& p) {
    const glm::dvec3 u = (p - box.lo) / (box.hi - box.lo);
    double f = 0.0;
    for (std::uint32_t c = 0; c < 8; ++c)
        f += idx.levels[leaf].coarser[c] * ((c & 1u) ? u.x : 1.0 - u.x) * ((c & 2u) ? u.y : 1.0 - u.y) * ((c & 4u) ? u.z : 1.0 - u.z);
    return double(idx.nodes[leaf].y & 0xFFu) - f;
}

std::unique_ptr<core::OctreeReader> phantomOctree(const test::TempDir& dir) {
    core::PhantomVoxelSource phantom({70, 52, 45});
    core::BuildOptions options;
    options.brickSize = 4;  // five levels
    core::JobContext job;
    core::OctreeBuilder(options).build(phantom, dir.file("p.hvo"), job);
    return core::OctreeReader::open(dir.file("p.hvo"));
}

bool withBrick(const glm::uvec4& nd) { return (nd.y & core::SpatialIndex::kLeafBit) && nd.x != core::SpatialIndex::kNone; }
}  // namespace

TEST(SpatialIndexLevels, TheFieldIsCoarserExactlyAtTheCornersACoarserLeafWithABrickTouches) {
    test::TempDir dir;
    const auto reader = phantomOctree(dir);
    ASSERT_GE(reader->levelCount(), 4u);
    std::mt19937 rng(21);
    std::size_t linked = 0, blending = 0, marked = 0, pastParent = 0, steepTotal = 0;
    float farthest = 0.0f;
    for (std::uint32_t trial = 0; trial < 12; ++trial) {
        const auto cut = test::randomCut(*reader, rng, 0.55 + 0.03 * trial);
        std::vector<std::uint32_t> slots;
        for (auto id : cut) slots.push_back(slotOf(id, trial));
        auto idx = core::SpatialIndex::build(*reader, cut, slots);
        idx.linkParents(*reader, [&](std::uint32_t id) { return slotOf(id, trial); });
        ASSERT_EQ(idx.levels.size(), idx.nodes.size());
        const auto boxes = leafBoxes(idx);
        std::size_t blendingHere = 0;
        float reachHere = 0.0f;
        for (std::size_t i = 0; i < idx.nodes.size(); ++i) {
            const auto& nd = idx.nodes[i];
            const auto& lv = idx.levels[i];
            const bool withParent = withBrick(nd) && nd.z != core::SpatialIndex::kNone &&
                                    reader->nodes()[nd.z].parent != core::hvo::kNoNode &&
                                    slotOf(reader->nodes()[nd.z].parent, trial) != core::SpatialIndex::kNone;
            if (!withParent) {
                EXPECT_EQ(lv, core::SpatialIndex::LevelLink{}) << "node " << i;
                continue;
            }
            ++linked;
            EXPECT_EQ(lv.ancestors[0], slotOf(reader->nodes()[nd.z].parent, trial));
            bool coarser = false, pastTheParent = false;
            float reach = 0.0f;
            for (std::uint32_t c = 0; c < 8; ++c) {
                const glm::dvec3 corner = glm::mix(boxes[i].lo, boxes[i].hi, glm::dvec3(c & 1u, (c >> 1) & 1u, (c >> 2) & 1u));
                bool touched = false;
                for (std::size_t j = 0; j < idx.nodes.size(); ++j)
                    touched = touched || (withBrick(idx.nodes[j]) && (idx.nodes[j].y & 0xFFu) < (nd.y & 0xFFu) &&
                                          contains(boxes[j], corner));
                const float f = lv.coarser[c];
                EXPECT_EQ(f > 0.0f, touched) << "trial " << trial << ", leaf " << i << ", corner " << c;
                if (touched) EXPECT_GE(f, 1.0f) << "a coarser leaf's field is at least its level";
                EXPECT_LE(f, core::SpatialIndex::kLevelSpan);
                coarser = coarser || touched;
                pastTheParent = pastTheParent || f > 1.0f;
                reach = std::max(reach, f);
                marked += touched;
            }
            EXPECT_EQ(lv.blends, coarser ? 1u : 0u);
            // Every ancestor the field reaches, resident (a missing one clamps the field below
            // it); none beyond.
            auto up = reader->nodes()[nd.z].parent;
            for (std::uint32_t k = 0; k < core::SpatialIndex::kLevelSpan; ++k) {
                if (k > 0 && k < std::uint32_t(std::ceil(reach))) {
                    up = reader->nodes()[up].parent;
                    ASSERT_NE(up, core::hvo::kNoNode);
                    EXPECT_EQ(lv.ancestors[k], slotOf(up, trial)) << "trial " << trial << ", leaf " << i << ", " << k + 1 << " up";
                    EXPECT_NE(lv.ancestors[k], core::SpatialIndex::kNone) << "the field reaches an ancestor not resident";
                } else if (k > 0) {
                    EXPECT_EQ(lv.ancestors[k], core::SpatialIndex::kNone) << "an ancestor past the field's reach";
                }
            }
            farthest = std::max(farthest, reach);
            reachHere = std::max(reachHere, reach);
            blendingHere += coarser;
            pastParent += pastTheParent;
        }
        EXPECT_EQ(idx.blendingLeaves, blendingHere);
        EXPECT_EQ(idx.levelReach, std::uint32_t(std::ceil(reachHere))) << "the cut's reach, for the shader's variant";
        std::size_t clampedHere = 0;
        for (const auto& lv : idx.levels) clampedHere += lv.clamped;
        EXPECT_EQ(idx.steepLeaves, clampedHere);
        EXPECT_LE(idx.steepLeaves, blendingHere);
        blending += blendingHere;
        steepTotal += idx.steepLeaves;
    }
    std::printf("%zu leaves linked to their parents, %zu of them blending (%zu past the parent, %zu clamped where an "
                "ancestor is missing), %zu corners coarser; the field reaches %.2f levels up at most\n",
                linked, blending, pastParent, steepTotal, marked, farthest);
    EXPECT_GT(pastParent, 10u);
    EXPECT_GT(farthest, 2.0f) << "the cuts put leaves three levels apart";
    EXPECT_GT(blending, 100u);  // the cuts mix levels: the check has corners to find
    EXPECT_GT(linked, blending);  // and leaves with none
}

TEST(SpatialIndexLevels, LeavesSharingAFaceSeeTheSameFieldOnIt) {
    test::TempDir dir;
    const auto reader = phantomOctree(dir);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::size_t faces = 0, acrossLevels = 0, acrossTwo = 0, points = 0, clamped = 0;
    double largest = 0.0;
    for (std::uint32_t trial = 0; trial < 12; ++trial) {
        const auto cut = test::randomCut(*reader, rng, 0.55 + 0.03 * trial);
        std::vector<std::uint32_t> slots;
        for (auto id : cut) slots.push_back(id + 1);  // every node resident, as the working set keeps them
        auto idx = core::SpatialIndex::build(*reader, cut, slots);
        idx.linkParents(*reader, [](std::uint32_t id) { return id + 1; });
        const auto boxes = leafBoxes(idx);
        for (std::size_t i = 0; i < idx.nodes.size(); ++i) {
            if (!withBrick(idx.nodes[i]) || idx.nodes[i].z == 0) continue;
            for (std::size_t j = i + 1; j < idx.nodes.size(); ++j) {
                if (!withBrick(idx.nodes[j]) || idx.nodes[j].z == 0) continue;
                const glm::dvec3 lo = glm::max(boxes[i].lo, boxes[j].lo), hi = glm::min(boxes[i].hi, boxes[j].hi);
                const glm::dvec3 extent = hi - lo;
                const int flat = (extent.x == 0.0) + (extent.y == 0.0) + (extent.z == 0.0);
                if (flat != 1 || extent.x < 0.0 || extent.y < 0.0 || extent.z < 0.0) continue;  // not a shared face
                if (idx.levels[i].clamped || idx.levels[j].clamped) {  // none: every ancestor is resident
                    ++clamped;
                    continue;
                }
                ++faces;
                const auto di = idx.nodes[i].y & 0xFFu, dj = idx.nodes[j].y & 0xFFu;
                acrossLevels += di != dj;
                acrossTwo += di + 2 <= dj || dj + 2 <= di;
                for (int k = 0; k < 9; ++k) {  // the face's four corners, then random points
                    const glm::dvec3 t = k < 4 ? glm::dvec3(k & 1, (k >> 1) & 1, (k & 1) ^ ((k >> 1) & 1))
                                               : glm::dvec3(u01(rng), u01(rng), u01(rng));
                    const glm::dvec3 p = lo + t * extent;
                    const double a = fieldFrom(idx, i, boxes[i], p), b = fieldFrom(idx, j, boxes[j], p);
                    largest = std::max(largest, std::abs(a - b));
                    EXPECT_NEAR(a, b, 1e-5) << "trial " << trial << ", leaves " << i << " (depth " << di << ") and " << j
                                            << " (depth " << dj << ") at " << p.x << ", " << p.y << ", " << p.z;
                    ++points;
                }
            }
        }
    }
    std::printf("%zu shared faces (%zu between levels, %zu two or more apart; %zu beside a clamped leaf "
                "left out), %zu points: largest difference %.3g levels\n",
                faces, acrossLevels, acrossTwo, clamped, points, largest);
    EXPECT_GT(acrossLevels, 200u);
    EXPECT_GT(acrossTwo, 10u);
    EXPECT_EQ(clamped, 0u) << "with every node resident, the field reaches any level";
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
