#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/volume/RawVoxelSource.h"

namespace hvx::core {

/// A volume kept as one raw file per slice (a MetaImage whose ElementDataFile lists them, as
/// ITK and MetaIO write long micro-CT or microscopy stacks), streamed slice by slice: only the
/// slices asked for are read, never the whole list (VTK's reader had read it whole into memory).
/// Every file is checked to be there, a regular file of exactly one slice's bytes, before the
/// first read.
class SliceListVoxelSource final : public VoxelSource {
public:
    /// `options` describe the whole volume (dims[2] = the number of files, no header bytes);
    /// throws core::Error naming the first file that is missing or not one slice long.
    SliceListVoxelSource(std::vector<std::string> files, const RawVoxelSource::Options& options, std::string describe);
    ~SliceListVoxelSource() override;

    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return describe_; }
    std::vector<std::string> warnings() const override { return options_.warnings; }

private:
    std::vector<std::string> files_;
    RawVoxelSource::Options options_;
    RawVoxelSource::Options slice_;  // one file's: a single slice
    VolumeGeometry geometry_;
    std::string describe_;
};

}  // namespace hvx::core
