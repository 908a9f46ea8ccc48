#pragma once
#include <memory>

#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// A float32 volume as 16-bit integers with a rescale chosen to keep its precision: the values
/// in [physicalMin, physicalMax] span the whole int16 range, so the step is (max - min) / 65535
/// and every value is within half a step of what it was. Used to export float volumes to DICOM,
/// whose images are integers. It measures the largest error it made on what it has read.
///
/// Threading: one thread at a time (VoxelSource's contract).
class RescaledInt16Source final : public VoxelSource {
public:
    /// `inner` must be float32; [physicalMin, physicalMax] must hold all of its physical values
    /// (found by a first pass). Throws core::Error otherwise.
    RescaledInt16Source(std::unique_ptr<VoxelSource> inner, double physicalMin, double physicalMax);
    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return inner_->describe(); }
    std::vector<std::string> warnings() const override { return inner_->warnings(); }
    /// The largest |exported - original| physical difference over the slices read so far.
    double largestError() const { return largestError_; }

    /// The smallest and largest physical values of a float32 source, read once through.
    static std::pair<double, double> physicalRange(VoxelSource& source);

private:
    std::unique_ptr<VoxelSource> inner_;
    VolumeGeometry geometry_;
    std::vector<float> buffer_;
    double largestError_ = 0.0;
};

}  // namespace hvx::core
