#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// Reads MetaImage (.mha, .mhd), legacy VTK (.vtk) and VTK XML image (.vti) files through
/// VTK's readers, requesting slabs of slices by update extent from the one that can stream (the
/// XML reader); the others are read whole, once. MetaImage and VTK files follow the ITK
/// convention and are taken as LPS. (VoxelSourceFactory streams plain MetaImage and legacy VTK
/// files itself, as raw data: see MetaImageHeader and LegacyVtkHeader.)
///
/// VTK itself is in the reader module that VtkReaderLibrary loads on first use: the first
/// VtkImageSource (or libraryVersion()) loads it, and throws core::Error when it cannot.
class VtkImageSource final : public VoxelSource {
public:
    /// Opens the file and reads its information; throws core::Error naming it, also when VTK
    /// would have to hold more of it at once than half this machine's memory, or when an
    /// uncompressed XML file is too short for the voxels its extent announces.
    explicit VtkImageSource(std::string path);
    /// VTK's version as the reader module links it ("9.1.0"), or a sentence when the module
    /// cannot be loaded.
    static std::string libraryVersion();
    ~VtkImageSource() override;

    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return path_; }
    /// What the file leaves open (MetaImageHeader's and LegacyVtkHeader's warnings; for a VTK
    /// file, that it names no patient axes).
    std::vector<std::string> warnings() const override { return warnings_; }

    /// True for the file name extensions this source reads.
    static bool handles(const std::string& path);
    /// True for a MetaImage's extensions (.mha, .mhd), whatever their case.
    static bool isMetaImage(const std::string& path);
    /// True for a legacy VTK file's extension (.vtk), whatever its case.
    static bool isLegacyVtk(const std::string& path);

private:
    struct Impl;
    std::string path_;
    VolumeGeometry geometry_;
    std::vector<std::string> warnings_;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hvx::core
