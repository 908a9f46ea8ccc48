#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/volume/RawVoxelSource.h"

namespace hvx::core {

/// Streams raw voxels (i fastest, then j, then k) stored deflated from an offset of a file: a
/// zlib stream (a MetaImage's CompressedData) or a gzip one (a NRRD's gzip encoding), told
/// apart by their header, inflated forward as the slices are asked for; a slice before the last
/// one read starts the stream again. Data that ends or is corrupt before the voxels the header
/// promises is an error naming the file and the slice, never zeros; once the last slice is read
/// the stream must end, and its checksum must hold. Elements are converted as RawVoxelSource's.
class InflatedVoxelSource final : public VoxelSource {
public:
    /// Opens the file at options.headerBytes; throws core::Error naming it.
    InflatedVoxelSource(std::string path, const RawVoxelSource::Options& options);
    ~InflatedVoxelSource() override;
    InflatedVoxelSource(const InflatedVoxelSource&) = delete;
    InflatedVoxelSource& operator=(const InflatedVoxelSource&) = delete;

    /// Deflate (zlib, gzip) packs at most 1032 bytes into one (zlib's technical notes): throws
    /// core::Error naming `file` when `compressedBytes` cannot hold `bytes` once inflated, so
    /// that a header promising more than its data can hold is refused before anything is read.
    static void checkDeflatedCanHold(const std::string& file, std::uint64_t compressedBytes, double bytes);

    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return path_; }
    std::vector<std::string> warnings() const override { return options_.warnings; }

private:
    struct Stream;
    /// Starts inflating from the beginning of the data.
    void restart();
    /// After the last voxel: the stream must end there, its checksum right.
    void checkEnd();
    /// Inflates the next `bytes` of voxel data into dst (null: thrown away).
    void inflateInto(unsigned char* dst, std::uint64_t bytes);
    std::string path_;
    RawVoxelSource::Options options_;
    VolumeGeometry geometry_;
    std::unique_ptr<Stream> stream_;
    std::uint64_t position_ = 0;  // bytes of voxel data inflated so far
    std::vector<unsigned char> buffer_;  // file elements of a slab being converted
};

}  // namespace hvx::core
