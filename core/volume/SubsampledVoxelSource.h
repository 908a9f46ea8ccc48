#pragma once
#include <memory>
#include <vector>

#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Every `factor`-th voxel of another source along each axis: a quick preview volume with the
/// same patient placement (voxel 0 stays where it was; spacing grows by the factor). It reads
/// one input slice in `factor`, so a preview octree builds in a fraction of the full build.
///
/// Threading: as the wrapped source (one thread, increasing slices).
class SubsampledVoxelSource final : public VoxelSource {
public:
    SubsampledVoxelSource(std::unique_ptr<VoxelSource> source, std::uint32_t factor);
    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override;

private:
    std::unique_ptr<VoxelSource> source_;
    std::uint32_t factor_;
    VolumeGeometry geometry_;
    std::vector<std::byte> slice_;
};

}  // namespace hvx::core
