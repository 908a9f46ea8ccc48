#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "core/octree/HvoFormat.h"
#include "core/base/JobContext.h"
#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Options of an octree build, as `holovox-cli build` exposes them.
struct BuildOptions {
    std::uint32_t brickSize = 32;  ///< interior edge of a brick, in voxels
    std::uint32_t border = 2;      ///< replicated neighbour samples on each face (1..8)
    /// Nodes whose values all lie below this physical value (after rescale) store no payload.
    std::optional<double> emptyBelow;
    bool labels = false;  ///< label volume: inner nodes take the most frequent child value
    bool lossy8 = false;  ///< store 8-bit bricks quantised to each node's value range
    hvo::Codec codec = hvo::Codec::Zstd;
    int codecLevel = 0;  ///< 0 = the codec's fast default
    /// The DICOM modality code to record instead of the source's (a NIfTI names none: the user
    /// says what it is); empty keeps the source's.
    std::string modality;
};

/// What a finished build produced.
struct BuildReport {
    std::uint64_t nodeCount = 0;
    std::uint64_t emptyNodes = 0;
    std::uint64_t fileBytes = 0;
    std::uint64_t inputBytes = 0;
    double seconds = 0.0;
    double lossyRmsError = 0.0;
    double lossyMaxError = 0.0;
};

/// Streams a VoxelSource into a .hvo octree with bounded memory: it keeps only
/// brickSize + 2*border slices per level, so peak memory is O(width × height × brickSize)
/// whatever the depth. Filtering and compression run on ThreadPool::shared(); the next slab is
/// read while the current one is processed. The file is written under a temporary name and
/// renamed at the end (AtomicFileWriter).
///
/// Threading: build() runs on the calling (job) thread and blocks until done; it reports
/// progress and honours cancellation through the JobContext.
class OctreeBuilder {
public:
    explicit OctreeBuilder(BuildOptions options);
    /// Builds `output` from `source`. Throws core::Error (naming input or output) or
    /// core::Cancelled; on any throw, no output file exists.
    BuildReport build(VoxelSource& source, const std::string& output, JobContext& job);

private:
    /// Throws core::Error naming `name` when the build would hold more at once than this
    /// machine's memory (slices too large, or too many bricks), before anything is allocated.
    void checkMemory(const VolumeGeometry& g, const std::string& name) const;
    BuildOptions options_;
};

}  // namespace hvx::core
