#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/octree/Brick.h"
#include "core/base/Error.h"
#include "core/octree/HvoFormat.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// A brick whose payload fails its checksum or does not decode; names the node.
class CorruptBrickError : public Error {
public:
    CorruptBrickError(const std::string& msg, std::uint32_t node) : Error(msg), node_(node) {}
    std::uint32_t node() const { return node_; }

private:
    std::uint32_t node_;
};

/// Opens a .hvo file, validates its header, node table and structure, and reads bricks by
/// node id. The whole node table is kept in memory (64 bytes a node); payloads are read on
/// demand with pread.
///
/// Threading: after open(), every const method may be called from many threads at once.
class OctreeReader {
public:
    /// Opens and validates; throws core::Error naming the file and what is wrong. A split-voxel
    /// octree (version 2) is refused with a sentence unless `acceptSplitVoxels`: its bricks hold
    /// cells, not samples, and only split-aware code (info, its tests) reads them yet.
    static std::unique_ptr<OctreeReader> open(const std::string& path, bool acceptSplitVoxels = false);
    ~OctreeReader();
    OctreeReader(const OctreeReader&) = delete;
    OctreeReader& operator=(const OctreeReader&) = delete;

    const std::string& path() const { return path_; }
    const hvo::FileHeader& header() const { return header_; }
    const VolumeGeometry& geometry() const { return geometry_; }
    std::uint32_t brickSize() const { return header_.brickSize; }
    std::uint32_t border() const { return header_.border; }
    /// Samples along a brick edge, border included.
    std::uint32_t brickEdge() const { return header_.brickSize + 2 * header_.border; }
    int levelCount() const { return int(header_.levelCount); }
    const std::vector<hvo::NodeRecord>& nodes() const { return nodes_; }
    /// A split-voxel octree: geometry() is its grid of cells, sourceDims() the volume's voxels.
    bool splitVoxels() const { return (header_.flags & hvo::FileSplitVoxels) != 0; }
    std::array<std::uint32_t, 3> sourceDims() const;
    /// Reads, verifies and decompresses one node's brick. Throws CorruptBrickError.
    Brick readBrick(std::uint32_t node) const;

private:
    OctreeReader() = default;
    void load();

    std::string path_;
    int fd_ = -1;
    hvo::FileHeader header_{};
    VolumeGeometry geometry_;
    std::vector<hvo::NodeRecord> nodes_;
};

}  // namespace hvx::core
