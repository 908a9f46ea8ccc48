#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/volume/VolumeGeometry.h"
#include "dicom/DicomInstance.h"

namespace hvx::dicom {

/// One input plane of a volume: a frame of one file, with its position along the stack.
struct SliceRef {
    std::size_t instance = 0;  ///< index into SeriesVolume::instances
    std::uint32_t frame = 0;
    glm::dvec3 position{0.0};
    double along = 0.0;  ///< position projected on the slice normal (mm)
    double rescaleSlope = 1.0, rescaleIntercept = 0.0;
};

/// A volume assembled from (part of) a series: its sorted slices and exact patient geometry.
/// When the input spacing is not uniform (missing or irregular slices), the volume is defined
/// on a uniform grid at the smallest regular spacing and slices are interpolated linearly.
struct SeriesVolume {
    std::string seriesUid;
    std::string label;  ///< "CT #3 Abdomen", plus "(stack 2 of 2)" and what varies when a series split
    /// What tells this volume from the series' others at the same positions (a 4D series):
    /// "echo 2 (TE 20 ms)", "b 1000 (0.71, 0.71, 0)", "time 3"; empty for a plain volume.
    std::string varying;
    std::vector<DicomInstance> instances;
    std::vector<SliceRef> slices;  ///< sorted by position along the normal
    core::VolumeGeometry geometry;
    bool applyRescale = false;  ///< output is float32 in physical units (per-slice rescale differs)
    bool resample = false;      ///< output slices are interpolated between input slices
    double tiltDegrees = 0.0;   ///< angle between the stacking direction and the slice normal
    std::vector<std::string> warnings;  ///< clear, named, one sentence each
};

}  // namespace hvx::dicom
