#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/volume/FileElement.h"
#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Reads a headerless raw voxel file (i fastest, then j, then k), as described on the command
/// line or by a header (NRRD, MetaImage): dimensions, element type, byte order and an optional
/// header offset to skip. Elements Holovox does not store as they are (int8, 32- and 64-bit
/// integers, float64) are converted slab by slab (core::decodeElements); a float64 beyond
/// float32's range is an error naming the file and the slice.
class RawVoxelSource final : public VoxelSource {
public:
    struct Options {
        std::array<std::uint32_t, 3> dims{0, 0, 0};
        FileElement element = FileElement::Int16;  ///< in the file; kept as storedTypeOf(element)
        bool bigEndian = false;
        std::uint64_t headerBytes = 0;
        glm::dvec3 spacing{1.0, 1.0, 1.0};
        glm::dvec3 origin{0.0, 0.0, 0.0};  ///< LPS
        glm::dmat3 direction{1.0};         ///< LPS direction cosines (columns)
        std::string modality = "OT";
        /// A raw file says nothing of the patient: its axes are taken as L, P and S and the
        /// views draw "?" for them; its spacing is 1 mm unless given (VolumeGeometry's flags).
        bool orientationAssumed = true;
        bool spacingAssumed = true;
        std::vector<std::string> warnings;  ///< passed on by warnings() (e.g. from a NRRD header)
        /// The voxels may be followed by more bytes (a legacy VTK file's newline and other
        /// attributes); otherwise the file must end with them.
        bool trailingBytes = false;
        /// Compressed data (InflatedVoxelSource) of several volumes: the decompressed bytes
        /// before this one, and all the stream holds (0: this volume alone).
        std::uint64_t inflatedSkip = 0;
        std::uint64_t inflatedTotal = 0;
        /// The volume these options describe (not yet validated).
        VolumeGeometry geometry() const;
    };
    /// Options for data that a header describes (NRRD, MetaImage): its geometry (modality
    /// included), element type, byte order (ignored for single bytes), offset and warnings, to
    /// which the conversion's (core::conversionWarning) is added, naming `file`.
    static Options described(const VolumeGeometry& g, FileElement element, bool bigEndian, std::uint64_t headerBytes,
                             std::vector<std::string> warnings, const std::string& file);
    /// Opens the file and checks that its size matches the dimensions (or, with trailingBytes, holds
    /// them); throws core::Error.
    RawVoxelSource(std::string path, const Options& options);
    ~RawVoxelSource() override;
    RawVoxelSource(const RawVoxelSource&) = delete;
    RawVoxelSource& operator=(const RawVoxelSource&) = delete;

    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return path_; }
    std::vector<std::string> warnings() const override { return options_.warnings; }

private:
    /// Reads exactly `bytes` from `offset`; a short file is an error naming the byte.
    void readBytes(std::uint64_t offset, std::uint64_t bytes, unsigned char* out);
    std::string path_;
    Options options_;
    VolumeGeometry geometry_;
    int fd_ = -1;
    std::vector<unsigned char> buffer_;  // file elements of a slab being converted
};

}  // namespace hvx::core
