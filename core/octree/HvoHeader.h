#pragma once
#include <vector>

#include "core/base/AtomicFileWriter.h"
#include "core/octree/HvoFormat.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::core::hvo {

/// The header a build writes before its payloads (complete = 0): geometry, layout and the
/// options' flags. Shared by the voxel and the split-voxel builders.
FileHeader startHeader(const VolumeGeometry& g, const BuildOptions& opt, int levels);
/// Ends a build: the node table after the payloads, the header's counts, value range and
/// checksums, `complete` set, the header rewritten at offset 0, and the file committed (renamed
/// into place).
void finishFile(FileHeader& h, const std::vector<NodeRecord>& nodes, AtomicFileWriter& out);

}  // namespace hvx::core::hvo
