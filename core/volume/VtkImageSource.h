#pragma once
#include <memory>
#include <string>

#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Reads NIfTI (.nii, .nii.gz), MetaImage (.mha, .mhd), legacy VTK (.vtk) and VTK XML image
/// (.vti) files through VTK's readers, requesting slabs of slices by update extent so that
/// readers which can stream do. NIfTI orientation (qform, else sform) is converted from RAS
/// to LPS; MetaImage and VTK files follow the ITK convention and are taken as LPS.
///
/// VTK stays private to this class: no VTK type appears in the header.
class VtkImageSource final : public VoxelSource {
public:
    /// Opens the file and reads its information; throws core::Error naming it.
    explicit VtkImageSource(std::string path);
    /// VTK's version as linked ("9.1.0").
    static std::string libraryVersion();
    ~VtkImageSource() override;

    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return path_; }

    /// True for the file name extensions this source reads.
    static bool handles(const std::string& path);

private:
    struct Impl;
    std::string path_;
    VolumeGeometry geometry_;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hvx::core
