#pragma once
#include <string>

#include "core/base/JobContext.h"
#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Streams any VoxelSource into an attached, raw, little-endian LPS .nrrd file, slab by slab,
/// through AtomicFileWriter (no partial file survives an error).
class NrrdWriter {
public:
    /// Writes `source` to `path`; throws core::Error or core::Cancelled.
    static void write(VoxelSource& source, const std::string& path, JobContext& job);
};

}  // namespace hvx::core
