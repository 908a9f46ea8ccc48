#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/appearance/LabelTable.h"
#include "core/volume/VoxelSource.h"

namespace hvx::dicom {

/// A DICOM Segmentation object (SEG, binary or fractional) as a label map, read through DCMTK's
/// dcmseg: each segment's number is its label, placed by its frames' own positions
/// (PlanePositionSequence) and the shared orientation and pixel measures, on a grid of the
/// frames' rows and columns and one slice per SpacingBetweenSlices (or the smallest step
/// between frames) from the lowest frame to the highest; slices no frame covers are
/// background. A fractional segment takes the voxels at or above half its maximum. Where two
/// segments overlap the higher number is kept, and warnings() says how many voxels that was.
/// The segments' labels and recommended display colours (CIELab, converted to sRGB as 3D
/// Slicer does) are table().
///
/// Threading: one thread at a time (a core::VoxelSource).
class SegmentationSource final : public core::VoxelSource {
public:
    /// Whether `path` is a DICOM Segmentation object (its SOP class), reading only its header.
    static bool isSegmentation(const std::string& path);
    /// Reads the object; throws core::Error naming the file: not a SEG, frames without a
    /// position or a segment, frames not stacked along one normal or not on one slice grid,
    /// no orientation or pixel spacing, a frame that does not decode.
    explicit SegmentationSource(const std::string& path);
    ~SegmentationSource() override;

    const core::VolumeGeometry& geometry() const override;
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override;
    std::vector<std::string> warnings() const override;
    /// The segments: number, label and colour.
    const core::LabelTable& table() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hvx::dicom
