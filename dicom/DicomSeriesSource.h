#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/volume/VoxelSource.h"
#include "dicom/SeriesVolume.h"

namespace hvx::dicom {

/// A series volume as a core::VoxelSource: decodes its slices in order, a few at a time on
/// all cores, so a series streams into the octree builder without ever being held whole.
/// Applies per-slice rescale when the volume is float, replaces PixelPaddingValue (by -1024 HU
/// for CT, else the lowest value), and interpolates slices when the volume was resampled.
///
/// Threading: one thread at a time (uses ThreadPool::shared() internally).
class DicomSeriesSource final : public core::VoxelSource {
public:
    explicit DicomSeriesSource(SeriesVolume volume);
    const core::VolumeGeometry& geometry() const override { return volume_.geometry; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override;
    /// What the stacking assumed or made up (missing slices interpolated, resampling...).
    std::vector<std::string> warnings() const override { return volume_.warnings; }
    const SeriesVolume& volume() const { return volume_; }
    /// The physical value that pixels marked as padding take in `v` (its geometry finished):
    /// -1024 HU for CT where the stored type holds it, else the lowest stored value.
    static double paddingValue(const SeriesVolume& v);

private:
    /// Padding as a stored value of the first slice's rescale, before rounding and clamping.
    static double paddingStoredOf(const SeriesVolume& v);
    const std::vector<std::int32_t>& input(std::size_t slice);
    template <class T>
    void writeSlice(std::uint32_t z, T* out);

    SeriesVolume volume_;
    std::map<std::size_t, std::vector<std::int32_t>> decoded_;  // input slice -> stored values
    double paddingStored_ = 0.0;
    double paddingPhysical_ = 0.0;  ///< what padding becomes under applyRescale (-1024 HU for CT)
};

}  // namespace hvx::dicom
