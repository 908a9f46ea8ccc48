#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/octree/OctreeReader.h"

namespace hvx::test {

/// A dense volume of doubles, for computing what an octree must contain independently of the
/// builder's streaming code.
struct DenseVolume {
    std::array<std::uint32_t, 3> dims{};
    std::vector<double> values;
    /// Value at (i, j, k) with each coordinate clamped into the volume.
    double clamped(long i, long j, long k) const;
};

/// The box-filtered (or, for labels, mode-filtered) pyramid of a volume, with values rounded to
/// the scalar type at every level, exactly as .hvo defines inner nodes.
std::vector<DenseVolume> referencePyramid(const DenseVolume& level0, int levels, core::ScalarType type, bool labels);

/// Checks every sample of every non-empty brick, border included, against the pyramid, and
/// that node ranges cover their bricks and their children. Reports through gtest.
void expectOctreeMatches(const core::OctreeReader& reader, const std::vector<DenseVolume>& pyramid);

}  // namespace hvx::test
