#include <gtest/gtest.h>

#include "core/octree/OctreeLayout.h"

using hvx::core::OctreeLayout;
namespace hvo = hvx::core::hvo;

TEST(OctreeLayout, LevelsAndNodeGridsForNonCubicVolume) {
    const OctreeLayout l({100, 50, 10}, 32);
    ASSERT_EQ(l.levelCount(), 3);
    EXPECT_EQ(l.levelNodes(0), (OctreeLayout::Dims{4, 2, 1}));
    EXPECT_EQ(l.levelDims(1), (OctreeLayout::Dims{50, 25, 5}));
    EXPECT_EQ(l.levelNodes(1), (OctreeLayout::Dims{2, 1, 1}));
    EXPECT_EQ(l.levelNodes(2), (OctreeLayout::Dims{1, 1, 1}));
    // Branch on need: 8 + 2 + 1 nodes, not a padded 16 + 4 + 1... cube.
    EXPECT_EQ(l.nodes().size(), 11u);
}

TEST(OctreeLayout, SingleVoxelVolumeIsOneRootLeaf) {
    const OctreeLayout l({1, 1, 1}, 32);
    ASSERT_EQ(l.levelCount(), 1);
    ASSERT_EQ(l.nodes().size(), 1u);
    EXPECT_EQ(l.nodes()[0].parent, hvo::kNoNode);
    EXPECT_EQ(l.nodes()[0].firstChild, hvo::kNoNode);
    EXPECT_EQ(l.nodes()[0].level, 0);
}

TEST(OctreeLayout, BreadthFirstWithContiguousChildrenAndConsistentLinks) {
    const OctreeLayout l({300, 7, 129}, 16);
    const auto& nodes = l.nodes();
    std::size_t perLevel[32] = {};
    for (std::uint32_t i = 0; i < nodes.size(); ++i) {
        const auto& n = nodes[i];
        ++perLevel[n.level];
        EXPECT_EQ(l.nodeId(n.level, n.x, n.y, n.z), i);
        if (i > 0) {
            EXPECT_GE(nodes[i - 1].level, n.level) << "levels must not increase along the table";
        }
        if (n.firstChild == hvo::kNoNode) {
            EXPECT_EQ(n.level, 0);
            continue;
        }
        std::uint32_t c = n.firstChild;
        for (std::uint32_t o = 0; o < 8; ++o) {
            if (!(n.childMask & (1u << o))) continue;
            const auto& ch = nodes[c];
            EXPECT_EQ(ch.parent, i);
            EXPECT_EQ(ch.level + 1, n.level);
            EXPECT_EQ(ch.x, 2 * n.x + (o & 1));
            EXPECT_EQ(ch.y, 2 * n.y + ((o >> 1) & 1));
            EXPECT_EQ(ch.z, 2 * n.z + ((o >> 2) & 1));
            ++c;
        }
    }
    for (int lv = 0; lv < l.levelCount(); ++lv) {
        const auto& g = l.levelNodes(lv);
        EXPECT_EQ(perLevel[lv], std::size_t(g[0]) * g[1] * g[2]) << "level " << lv;
    }
}
