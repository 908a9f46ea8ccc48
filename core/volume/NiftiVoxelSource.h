#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/volume/NiftiHeader.h"
#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Streams one 3D volume of a NIfTI-1 file (.nii or .nii.gz, through zlib, which reads both)
/// slice by slice in file order, converting the file's type to the stored one (int8 to int16;
/// 32- and 64-bit integers and float64 to float32) and its byte order to the host's. The
/// placement is NiftiHeader's (sform, else qform, else pixdim). A 4D file holds `volumes()`
/// volumes; the constructor picks one (0-based). A NIfTI names no modality: the volume is "OT"
/// unless a BIDS sidecar beside it (NAME.json, as dcm2niix writes) gives its Modality.
///
/// Threading: one thread at a time (VoxelSource's contract).
class NiftiVoxelSource final : public VoxelSource {
public:
    /// Opens `path` and reads its header; throws core::Error with a sentence naming the file.
    explicit NiftiVoxelSource(std::string path, std::uint32_t volume = 0);
    ~NiftiVoxelSource() override;
    NiftiVoxelSource(const NiftiVoxelSource&) = delete;
    NiftiVoxelSource& operator=(const NiftiVoxelSource&) = delete;

    static bool handles(const std::string& path);

    const VolumeGeometry& geometry() const override { return header_.geometry; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return path_; }
    std::vector<std::string> warnings() const override;

    const NiftiHeader& header() const { return header_; }
    std::uint32_t volumes() const { return header_.volumes; }

private:
    struct Gz;
    std::string path_;
    std::uint32_t volume_;
    NiftiHeader header_;
    std::unique_ptr<Gz> gz_;
    std::vector<unsigned char> buffer_;
};

}  // namespace hvx::core
