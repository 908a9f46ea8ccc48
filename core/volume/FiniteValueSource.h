#pragma once
#include <memory>

#include "core/volume/VoxelSource.h"

namespace hvx::core {

/// A float32 source whose every value is checked as it is read: a NaN (SPM's and FSL's "no
/// value" outside a mask) or an infinity is refused, naming the file, the slice and how many
/// such values it holds, because the octree, the transfer functions and the measurements take a
/// stored value as a number. Every other scalar type passes through untouched.
///
/// Threading: as the wrapped source (one thread, increasing slices).
class FiniteValueSource final : public VoxelSource {
public:
    /// "2 NaN (not-a-number) values and 1 infinite value" among `count` floats, empty when every
    /// one is a number: the sentence every float reader (files, DICOM float pixels) refuses with.
    static std::string nonFinite(const float* values, std::size_t count);
    /// Wraps `source` when its values are float32; returns it as it is otherwise.
    static std::unique_ptr<VoxelSource> wrap(std::unique_ptr<VoxelSource> source);

    explicit FiniteValueSource(std::unique_ptr<VoxelSource> source) : source_(std::move(source)) {}
    const VolumeGeometry& geometry() const override { return source_->geometry(); }
    void readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) override;
    std::string describe() const override { return source_->describe(); }
    std::vector<std::string> warnings() const override { return source_->warnings(); }
    /// The source whose values are checked.
    const VoxelSource& inner() const { return *source_; }

private:
    std::unique_ptr<VoxelSource> source_;
};

}  // namespace hvx::core
