#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/volume/FileElement.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// The fields of a MetaImage header (.mha, .mhd; ITK's MetaIO) that describe and place a volume:
/// DimSize, ElementType, ElementSpacing (else ElementSize), Offset (or Origin, Position), the
/// direction cosines (TransformMatrix, or Rotation, Orientation: row a is axis a's direction in
/// LPS, as ITK writes it), byte order, compression and where the data lies (ElementDataFile,
/// HeaderSize). MetaImage files follow the ITK convention and are taken as LPS.
///
/// A plain file (3-D, binary, one channel of any integer or float type, in one data file) is
/// streamed by Holovox: RawVoxelSource, which checks its size, or InflatedVoxelSource when its
/// data is compressed; so is a list of 2-D slice files (ElementDataFile = LIST, or a MetaIO file
/// pattern such as "slice%03d.raw 1 100 1"), uncompressed, by SliceListVoxelSource; so is ASCII
/// data (BinaryData = False) in one file, by AsciiVoxelSource, which checks every value. Anything
/// else (several channels, ASCII slice files, ...) goes to VTK's reader (VtkImageSource), which
/// reads it whole, and streamReason says why.
class MetaImageHeader {
public:
    VolumeGeometry geometry;      ///< dims, spacing, origin, direction; scalarType when streamable
    FileElement element = FileElement::UInt8;  ///< ElementType, when streamable
    bool bigEndian = false;
    std::string dataFile;         ///< the file that holds the voxels (the header's own for LOCAL)
    std::vector<std::string> sliceFiles;  ///< the files of a slice each, in order, when listed
    std::uint64_t dataOffset = 0; ///< where they begin in it
    bool compressed = false;
    bool ascii = false;           ///< BinaryData = False: the voxels are written as text
    int channels = 1;             ///< ElementNumberOfChannels: values per voxel
    std::uint64_t compressedBytes = 0;  ///< CompressedDataSize, 0 when not given
    std::vector<std::string> warnings;  ///< what the header leaves open, one sentence each
    /// Empty when Holovox streams the data itself; otherwise why not ("it has 3 channels").
    std::string streamReason;

    /// Parses the header; throws core::Error naming the file and the bad field.
    static MetaImageHeader read(const std::string& path);
};

}  // namespace hvx::core
