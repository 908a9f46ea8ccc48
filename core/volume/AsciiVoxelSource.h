#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "core/volume/RawVoxelSource.h"

namespace hvx::core {

/// Reads voxels written as text, one number per voxel separated by blanks (MetaImage with
/// BinaryData = False, legacy VTK files in ASCII), i fastest, from the options' header offset.
/// Streamed: slabs are parsed in order as they are asked for, and the file's text is never held
/// whole. Nothing is assumed: a token that is not a number, a fraction or an out-of-range value
/// in an integer image, text that ends before the last voxel, and (unless trailingBytes) more
/// numbers than voxels are each a core::Error naming the file and the voxel. A file too short to
/// hold the header's voxel count at all (at least a digit and a blank each) is refused when
/// opened, before anything is read or allocated for it.
class AsciiVoxelSource final : public VoxelSource {
public:
    /// `options` as for RawVoxelSource: headerBytes is where the text begins; bigEndian is
    /// ignored; trailingBytes lets other text follow the voxels (a legacy VTK file's further
    /// attributes).
    AsciiVoxelSource(std::string path, const RawVoxelSource::Options& options);
    ~AsciiVoxelSource() override;
    AsciiVoxelSource(const AsciiVoxelSource&) = delete;
    AsciiVoxelSource& operator=(const AsciiVoxelSource&) = delete;

    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return path_; }
    std::vector<std::string> warnings() const override { return options_.warnings; }

private:
    /// The next blank-separated token; empty at the end of the file.
    std::string_view nextToken();
    /// Parses the next `n` values into `out` as the file's element type, in this machine's order.
    void parseValues(std::uint64_t n, unsigned char* out);
    /// Goes back to the first voxel.
    void rewind();
    /// "voxel (i, j, k), value number n": where value `index` (0-based) lies.
    std::string where(std::uint64_t index) const;

    std::string path_;
    RawVoxelSource::Options options_;
    VolumeGeometry geometry_;
    std::FILE* file_ = nullptr;
    std::vector<char> text_;   // the file's text being parsed: [begin_, end_) not yet read
    std::size_t begin_ = 0, end_ = 0;
    bool eof_ = false;
    std::uint64_t parsed_ = 0;  // values parsed so far
    std::vector<unsigned char> buffer_;  // elements of a slab being converted
    std::vector<unsigned char> skipped_;  // values parsed to reach a later slab
};

}  // namespace hvx::core
