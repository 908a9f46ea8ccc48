#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// A volume that can be read slab by slab along k, in increasing order, so that builders never
/// need the whole volume in memory. Implementations: raw files, VTK-readable images, the
/// procedural phantom, and (in dicom/) DICOM series.
///
/// Threading: one thread at a time; readSlices is called with increasing firstSlice.
class VoxelSource {
public:
    virtual ~VoxelSource() = default;
    /// Geometry of the volume; valid right after construction.
    virtual const VolumeGeometry& geometry() const = 0;
    /// Reads `count` whole k-slices starting at `firstSlice` into dst (dims[0]*dims[1]*count
    /// voxels of geometry().scalarType, i fastest). Throws core::Error naming the input.
    virtual void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) = 0;
    /// Human-readable name of the input, used in messages.
    virtual std::string describe() const = 0;
    /// Sentences about what the input leaves open or contradicts (e.g. a NIfTI qform and sform
    /// that disagree), each naming the input; shown before a build.
    virtual std::vector<std::string> warnings() const { return {}; }
};

}  // namespace hvx::core
