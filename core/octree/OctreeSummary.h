#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/octree/OctreeReader.h"

namespace hvx::core {

/// Figures `holovox-cli info` prints about an .hvo file: geometry, levels, nodes per level,
/// empty fraction, compression ratio and size on disk.
struct OctreeSummary {
    struct Level {
        std::uint32_t dims[3];
        std::uint32_t nodes[3];
        std::uint64_t nodeCount = 0;
        std::uint64_t emptyCount = 0;
        std::uint64_t payloadBytes = 0;
    };
    std::vector<Level> levels;  ///< index = level (0 = leaves)
    std::uint64_t nodeCount = 0;
    std::uint64_t emptyCount = 0;
    std::uint64_t fileBytes = 0;
    std::uint64_t volumeBytes = 0;   ///< uncompressed voxel data of the source
    std::uint64_t rawBrickBytes = 0; ///< uncompressed bytes of the stored bricks

    /// Computes the summary from an open reader's header and node table (no payload reads).
    static OctreeSummary of(const OctreeReader& reader);
    /// Multi-line text for the terminal.
    std::string format(const OctreeReader& reader) const;
};

}  // namespace hvx::core
