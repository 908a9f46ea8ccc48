#include "core/volume/NiftiVoxelSource.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>

#include "core/base/Error.h"
#include "core/volume/VolumeChoice.h"

namespace hvx::core {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(), [](char a, char b) { return std::tolower(a) == b; });
}

}  // namespace

struct NiftiVoxelSource::Gz {
    gzFile file = nullptr;
    ~Gz() {
        if (file) gzclose(file);
    }
};

bool NiftiVoxelSource::handles(const std::string& path) { return endsWith(path, ".nii") || endsWith(path, ".nii.gz"); }

NiftiVoxelSource::NiftiVoxelSource(std::string path, std::uint32_t volume)
    : path_(std::move(path)), volume_(volume), gz_(std::make_unique<Gz>()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec)) throw Error(path_ + ": no such file");
    gz_->file = gzopen(path_.c_str(), "rb");
    if (!gz_->file) throw Error(path_ + ": cannot open");
    gzbuffer(gz_->file, 1u << 18);
    unsigned char raw[348];
    const int got = gzread(gz_->file, raw, sizeof raw);
    if (got < 0) throw Error(path_ + ": not a readable NIfTI file (gzip data is corrupt)");
    header_ = NiftiHeader::parse(raw, std::size_t(got), path_);
    VolumeChoice{path_, header_.volumes, volume_}.check();
    if (!endsWith(path_, ".gz")) {  // uncompressed: the size is known, check it now
        const std::uint64_t need = header_.voxOffset + std::uint64_t(header_.volumes) *
                                                           header_.geometry.voxelCount() * std::uint64_t(elementSize(header_.element));
        const auto size = std::filesystem::file_size(path_, ec);
        if (!ec && size < need)
            throw Error(path_ + ": is truncated: its header needs " + std::to_string(need) + " bytes, the file has " +
                        std::to_string(size));
    }
}

NiftiVoxelSource::~NiftiVoxelSource() = default;

std::vector<std::string> NiftiVoxelSource::warnings() const {
    std::vector<std::string> w;
    for (const auto& s : header_.warnings) w.push_back(path_ + ": " + s);
    if (header_.volumes > 1) w.push_back(VolumeChoice{path_, header_.volumes, volume_}.note());
    return w;
}

void NiftiVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const auto& g = header_.geometry;
    if (std::uint64_t(firstSlice) + count > g.dims[2]) throw Error(path_ + ": slices beyond the volume requested");
    const std::uint64_t sliceVoxels = std::uint64_t(g.dims[0]) * g.dims[1];
    const std::uint64_t fileSlice = sliceVoxels * elementSize(header_.element);
    const std::uint64_t offset =
        header_.voxOffset + (std::uint64_t(volume_) * g.dims[2] + firstSlice) * fileSlice;
    // gzseek goes forward by decompressing; backwards it rewinds. Slices come in order.
    if (gzseek64(gz_->file, z_off64_t(offset), SEEK_SET) != z_off64_t(offset))
        throw Error(path_ + ": is truncated or corrupt before slice " + std::to_string(firstSlice));
    std::uint32_t slice = firstSlice;  // the next slice to read, for messages
    decodeSlices(header_.element, header_.bigEndian, sliceVoxels, firstSlice, count, buffer_, dst,
                 [&](unsigned char* into, std::uint64_t bytes) {
                     for (std::uint64_t at = 0; at < bytes;) {
                         const unsigned step = unsigned(std::min<std::uint64_t>(bytes - at, 1u << 30));
                         const int got = gzread(gz_->file, into + at, step);
                         if (got <= 0)
                             throw Error(path_ + ": is truncated or corrupt at slice " +
                                         std::to_string(slice + at / fileSlice) + " of " + std::to_string(g.dims[2]));
                         at += std::uint64_t(got);
                     }
                     slice += std::uint32_t(bytes / fileSlice);
                 }, path_);
}

}  // namespace hvx::core
