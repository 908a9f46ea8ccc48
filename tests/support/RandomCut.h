#pragma once
#include <cstdint>
#include <random>
#include <vector>

#include "core/octree/OctreeReader.h"

namespace hvx::test {

/// A random valid cut of an octree: from the root, each node is refined with the given
/// probability (leaves never), so cuts mix levels the way a working set does.
inline std::vector<std::uint32_t> randomCut(const core::OctreeReader& reader, std::mt19937& rng,
                                            double refineProbability) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<std::uint32_t> cut, todo{0};
    while (!todo.empty()) {
        const auto id = todo.back();
        todo.pop_back();
        const auto& n = reader.nodes()[id];
        if (n.level == 0 || u(rng) > refineProbability) {
            cut.push_back(id);
            continue;
        }
        for (std::uint32_t c = 0; c < std::uint32_t(__builtin_popcount(n.childMask)); ++c) todo.push_back(n.firstChild + c);
    }
    return cut;
}

}  // namespace hvx::test
