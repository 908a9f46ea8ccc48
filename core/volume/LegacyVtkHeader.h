#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/volume/FileElement.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// The header of a legacy VTK file (.vtk) that holds an image: `DATASET STRUCTURED_POINTS` with
/// DIMENSIONS, SPACING (or ASPECT_RATIO), ORIGIN, then POINT_DATA and its SCALARS. DIRECTION is
/// no keyword of the format (neither VTK nor ITK writes or reads it): nine numbers that some
/// writers add, by rows or by columns nobody defines, so one is taken, with a warning, only
/// where both readings agree, and only for data Holovox streams (VTK's reader refuses it).
/// VTK files name no patient axes; like ITK, which writes them, Holovox takes them as LPS.
///
/// A plain image (point data whose first attribute is one-component SCALARS of any integer or
/// float type but `long`, whose size is the platform's) is streamed by Holovox: BINARY by
/// RawVoxelSource (VTK's binary data is big-endian, x fastest, and its size is checked), ASCII
/// by AsciiVoxelSource (every value checked). Anything else (cell data, field data, several
/// components, ...) goes to VTK's own reader (VtkImageSource), which reads the whole image, and
/// streamReason says why.
class LegacyVtkHeader {
public:
    VolumeGeometry geometry;  ///< scalarType: storedTypeOf(element) when streamable
    FileElement element = FileElement::UInt8;  ///< the SCALARS type, when streamable
    std::uint64_t dataOffset = 0;  ///< where the voxels begin: after the LOOKUP_TABLE line
    bool ascii = false;            ///< ASCII: the voxels are written as text
    std::vector<std::string> warnings;  ///< what the header leaves open, one sentence each
    /// Empty when Holovox streams the data itself; otherwise why not ("its SCALARS have 3 components").
    std::string streamReason;

    /// Parses the header (at most its first 64 KiB); throws core::Error naming the file and the
    /// bad field for a header that is not a legacy VTK image or that contradicts itself.
    static LegacyVtkHeader read(const std::string& path);

private:
    bool direction_ = false;  // the header holds a DIRECTION
    static LegacyVtkHeader parse(const std::string& path);
};

}  // namespace hvx::core
