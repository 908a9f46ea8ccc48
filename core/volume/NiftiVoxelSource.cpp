#include "core/volume/NiftiVoxelSource.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "core/base/Error.h"
#include "core/volume/InflatedVoxelSource.h"
#include "core/volume/VolumeChoice.h"

namespace hvx::core {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(), [](char a, char b) { return std::tolower(a) == b; });
}

// The modality a BIDS sidecar beside the file names (dcm2niix writes NAME.json beside
// NAME.nii.gz with "Modality": "CT"), empty when there is none; a sidecar that cannot be read
// is said in `warnings`.
std::string sidecarModality(const std::string& path, std::vector<std::string>& warnings) {
    const std::size_t cut = path.size() - (endsWith(path, ".nii.gz") ? 7 : 4);
    const std::string json = path.substr(0, cut) + ".json";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(json, ec)) return {};
    const auto size = std::filesystem::file_size(json, ec);
    std::ifstream in(json, std::ios::binary);
    std::string text;
    if (!ec && size <= (std::uint64_t(1) << 20) && in)
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    const auto doc = nlohmann::json::parse(text, nullptr, false);
    if (text.empty() || doc.is_discarded() || !doc.is_object()) {
        warnings.push_back("its BIDS sidecar " + json + " cannot be read as JSON (or is over 1 MiB): the modality is not known");
        return {};
    }
    const auto m = doc.find("Modality");
    if (m == doc.end()) return {};
    const std::string v = m->is_string() ? m->get<std::string>() : std::string();
    if (!VolumeGeometry::isModalityCode(v)) {
        warnings.push_back("its BIDS sidecar " + json + " gives Modality " + m->dump() + ", not a DICOM modality code");
        return {};
    }
    return v;
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
    if (const std::string m = sidecarModality(path_, header_.warnings); !m.empty()) header_.geometry.modality = m;
    VolumeChoice{path_, header_.volumes, volume_}.check();
    const std::uint64_t need = header_.voxOffset + std::uint64_t(header_.volumes) *
                                                       header_.geometry.voxelCount() * std::uint64_t(elementSize(header_.element));
    const auto size = std::filesystem::file_size(path_, ec);
    if (endsWith(path_, ".gz") && !ec) {  // compressed: its size bounds what it can hold
        InflatedVoxelSource::checkDeflatedCanHold(path_, size, double(need));
    } else {  // uncompressed: the size is known, check it now
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
