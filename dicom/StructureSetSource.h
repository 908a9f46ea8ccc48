#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/appearance/LabelTable.h"
#include "core/volume/VoxelSource.h"

namespace hvx::dicom {

/// A DICOM RT Structure Set (RTSTRUCT) rasterised onto an image's grid as a label map, read
/// through DCMTK's dcmrt. Each ROI's closed planar contours fill the voxels whose centres they
/// enclose on the slice they lie on, by the even-odd rule over all of that ROI's contours on the
/// slice (so an inner contour is a hole, as the standard and 3D Slicer read them); an ROI's
/// number is its label, a higher number drawn over a lower where they overlap (counted in
/// warnings()). Contours past the grid's first or last slice are left out and said; points,
/// open contours and contours that do not lie in one slice of the grid are refused or said.
/// The ROIs' names and display colours are table().
///
/// Threading: one thread at a time (a core::VoxelSource).
class StructureSetSource final : public core::VoxelSource {
public:
    /// Whether `path` is an RT Structure Set (its SOP class), reading only its header.
    static bool isStructureSet(const std::string& path);
    /// Reads the contours of `path` onto `grid` (the image's geometry: dims, spacing, origin,
    /// direction; its frame of reference must be the structure set's when both are known).
    /// Throws core::Error naming the file: not an RTSTRUCT, another frame of reference, a
    /// contour with too few points or off the grid's slices, no ROI to draw.
    StructureSetSource(const std::string& path, const core::VolumeGeometry& grid);
    ~StructureSetSource() override;

    const core::VolumeGeometry& geometry() const override;
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override;
    std::vector<std::string> warnings() const override;
    /// The ROIs: number, name and display colour.
    const core::LabelTable& table() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hvx::dicom
