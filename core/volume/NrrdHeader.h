#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/volume/FileElement.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// The parts of a NRRD header (teem's format) that place a volume in patient space: sizes,
/// type, encoding, byte order, space, space directions and space origin; a 4-D file's volumes. Used to write the
/// phantom and to recover orientation that VTK's NRRD reader ignores.
class NrrdHeader {
public:
    VolumeGeometry geometry;  ///< scalarType: storedTypeOf(element)
    FileElement element = FileElement::Int16;  ///< the file's type
    std::string encoding = "raw";
    bool bigEndian = false;
    std::string dataFile;  ///< detached data file as the header names it, empty when attached
    std::string dataPath;  ///< the file that holds the data: the header's own or dataFile beside it
    std::uint64_t headerBytes = 0;  ///< bytes before the data in its file: the header (attached), line and byte skips
    std::vector<std::string> warnings;  ///< what the header leaves open, one sentence each
    /// Volumes in the file: a 4-D NRRD (a 3D Slicer sequence) whose fourth, non-spatial axis
    /// lists them one after the other; 1 for a 3-D one.
    std::uint32_t volumes = 1;

    /// Parses a .nrrd/.nhdr header; throws core::Error naming the file and the bad field.
    static NrrdHeader read(const std::string& path);
    /// Header text for an attached raw, little-endian LPS volume.
    static std::string format(const VolumeGeometry& g);
};

}  // namespace hvx::core
