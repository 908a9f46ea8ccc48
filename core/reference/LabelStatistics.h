#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "core/appearance/LabelTable.h"
#include "core/octree/OctreeReader.h"

namespace hvx::core {

class JobContext;

/// Per-label statistics of a label map over its image, as 3D Slicer's Segment Statistics and
/// ITK-SNAP's label statistics give them: each label's volume (its voxels of the label map
/// times one voxel's volume) and the image's values at those voxels' centres (trilinear on the
/// image's finest level, so the label map may lie on another grid of the same frame), in the
/// image's physical units (HU for CT). Read from both octrees' level 0, brick by brick.
struct LabelStatistics {
    struct Row {
        std::uint64_t voxels = 0;
        double volumeMl = 0;
        std::uint64_t sampled = 0;  ///< voxels whose centre lies in the image (the mean's count)
        double mean = 0, sd = 0, min = 0, max = 0;  ///< sd: the population SD
        bool exact = true;  ///< false when some of its image values come from bricks stored without them
    };
    std::map<int, Row> rows;  ///< by label (0, the background, is left out)
    std::string units;        ///< "HU" for CT, else empty
    /// Labels some of whose voxels lie outside the image, or with approximate image values
    /// (bricks stored without values), named: empty when none.
    std::string note;

    /// Throws core::Error when `labels` is not a label map, CorruptBrickError for a brick that
    /// cannot be read; honours `job`'s cancellation and reports progress.
    static LabelStatistics compute(const OctreeReader& image, const OctreeReader& labels, JobContext& job);
    /// CSV, one row per label: label,name,voxels,volume_ml,voxels_in_image,mean,sd,min,max,units,exact
    /// (names from `table` when given, quoted as RFC 4180 says).
    std::string csv(const LabelTable* table) const;
};

}  // namespace hvx::core
