#pragma once
#include <cstdint>
#include <string>

#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// A procedural CT phantom of a torso in Hounsfield units (int16, slope 1, intercept 0):
/// body outline with a fat layer, soft tissue, lungs (air), heart on the patient's left, liver
/// on the patient's right, kidneys, a spine and ribs with cortical bone shells, and contrast
/// filled aorta and vessels, plus noise. It is a pure function of (voxel index, dims, seed), so
/// any size streams without ever existing as a file, and every run gives the same voxels.
///
/// Threading: readSlices spreads work over ThreadPool::shared().
class PhantomVoxelSource final : public VoxelSource {
public:
    /// dims of the grid; fieldOfViewMm is the physical extent along each axis (500 mm default,
    /// spacing = fov / dims); seed picks noise and vessel paths.
    PhantomVoxelSource(std::array<std::uint32_t, 3> dims, std::uint64_t seed = 1,
                       glm::dvec3 fieldOfViewMm = {500.0, 500.0, 500.0}, double noiseHu = 15.0);

    const VolumeGeometry& geometry() const override { return geometry_; }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override;

    /// Hounsfield value of one voxel (the same value readSlices writes).
    std::int16_t voxel(std::uint32_t i, std::uint32_t j, std::uint32_t k) const;

private:
    void fillRow(std::uint32_t j, std::uint32_t k, std::int16_t* row) const;
    double tissueAt(double u, double v, double w) const;

    VolumeGeometry geometry_;
    std::uint64_t seed_;
    double noiseHu_;
    double vesselPhase_[4];
};

}  // namespace hvx::core
