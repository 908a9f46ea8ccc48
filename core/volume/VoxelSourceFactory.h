#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "core/volume/RawVoxelSource.h"
#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Picks the VoxelSource for an input name: `phantom:XxYxZ[:seed]`, .raw (with RawOptions),
/// .nrrd/.nhdr (raw encoding, streamed), .nii/.nii.gz (NiftiVoxelSource), or anything
/// VtkImageSource reads.
class VoxelSourceFactory {
public:
    /// Opens `input`; `raw` describes headerless files (dims must be set for .raw); `volume`
    /// picks one volume (0-based) of a 4D file. A float volume's values are checked as they are
    /// read (FiniteValueSource). Throws core::Error naming the input.
    static std::unique_ptr<VoxelSource> open(const std::string& input, const RawVoxelSource::Options& raw = {},
                                             std::uint32_t volume = 0);
    /// How many volumes `input` holds: a 4-D NIfTI's or NRRD's count, 1 for anything else.
    /// Throws core::Error when the header cannot be read.
    static std::uint32_t volumesIn(const std::string& input);
    /// Parses "XxYxZ" (each 1..2^20); throws core::Error otherwise.
    static std::array<std::uint32_t, 3> parseDims(const std::string& text);

private:
    static std::unique_ptr<VoxelSource> openFormat(const std::string& input, const RawVoxelSource::Options& raw,
                                                   std::uint32_t volume);
};

}  // namespace hvx::core
