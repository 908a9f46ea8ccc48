#pragma once
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "core/appearance/TransferFunction.h"
#include "core/camera/DisplayModel.h"
#include "core/octree/OctreeReader.h"

namespace hvx::core {

/// Where a volume shows anything: the index-space box of the octree nodes whose value range
/// the transfer function does not leave transparent (from the node table's min/max, no brick
/// read), at the finest level with at most `maxNodes` nodes. Light-field framing fits this box,
/// not the volume's, to the display (an MRI's air does not take the screen).
struct ContentBox {
    glm::dvec3 lo{0.0}, hi{0.0};  ///< voxel indices: the first voxel, and one past the last, along i, j, k
    /// The eight corners in patient space (LPS mm), the voxels' outer faces.
    std::vector<glm::dvec3> corners(const VolumeGeometry& g) const;
    /// The box, or none when the transfer function shows nothing of the volume; with
    /// `everyValue` (MIP) every non-empty node counts.
    static std::optional<ContentBox> of(const OctreeReader& reader, const TransferFunction& tf, bool everyValue = false,
                                        std::size_t maxNodes = 32768);
    /// A display's default framing (DisplayModel::frame) of what `tf` shows of the volume, or of
    /// the whole volume when it shows nothing (`found` says which): the one framing of the CLI,
    /// the MPI renderer and the GUI.
    static DisplayModel::Framing framing(const DisplayModel& display, const OctreeReader& reader, const TransferFunction& tf,
                                         bool everyValue, const glm::dvec3& right, const glm::dvec3& up, bool trueDepth,
                                         bool* found = nullptr);
};

}  // namespace hvx::core
