#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/octree/Brick.h"
#include "core/octree/OctreeLayout.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// A volume read back from an octree's full-resolution level: its stored values exactly, slab by
/// slab, one row of level-0 bricks held at a time. Lets a build start from an octree (a
/// split-voxel octree from the volume the workstation has open, when its DICOM files are gone
/// or on a PACS). Refused in a sentence: a split-voxel octree (cells, not voxels) and an octree
/// whose bricks are stored lossily (its values are not the volume's).
///
/// Threading: one thread at a time (VoxelSource).
class OctreeVoxelSource final : public VoxelSource {
public:
    explicit OctreeVoxelSource(std::shared_ptr<const OctreeReader> reader);
    const VolumeGeometry& geometry() const override { return reader_->geometry(); }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return reader_->path(); }
    /// An octree built with an empty threshold: its bricks wholly below it read back as their
    /// smallest value.
    std::vector<std::string> warnings() const override;

private:
    void loadRow(std::uint32_t row);

    std::shared_ptr<const OctreeReader> reader_;
    OctreeLayout layout_;
    std::uint32_t row_ = ~0u;    // the row of level-0 bricks held
    std::vector<Brick> bricks_;  // that row's bricks, x fastest
};

}  // namespace hvx::core
