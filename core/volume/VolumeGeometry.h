#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/volume/DisplayWindow.h"
#include "core/volume/ScalarType.h"

namespace hvx::core {

/// Everything needed to place a voxel grid in the patient and to turn stored values into
/// physical ones. Patient space is DICOM LPS: +x towards the patient's left, +y posterior,
/// +z superior. Stored value v maps to v * rescaleSlope + rescaleIntercept (HU for CT).
struct VolumeGeometry {
    std::array<std::uint32_t, 3> dims{0, 0, 0};   ///< voxels along i, j, k
    glm::dvec3 spacing{1.0, 1.0, 1.0};            ///< mm between voxel centres along i, j, k
    glm::dvec3 origin{0.0, 0.0, 0.0};             ///< LPS position (mm) of voxel (0,0,0)'s centre
    glm::dmat3 direction{1.0};                    ///< columns: unit LPS directions of i, j, k
    ScalarType scalarType = ScalarType::Int16;
    double rescaleSlope = 1.0;
    double rescaleIntercept = 0.0;
    double valueMin = 0.0;  ///< smallest stored value in the volume (0 when unknown)
    double valueMax = 0.0;  ///< largest stored value in the volume (0 when unknown)
    std::string modality = "OT";  ///< DICOM modality code (CT, MR, ...), "OT" when unknown
    /// DICOM Frame of Reference UID: volumes sharing one share patient coordinates; empty when
    /// the source has none (NIfTI, NRRD, raw: their LPS is all there is to align them by).
    std::string frameOfReferenceUid;
    bool isLabel = false;         ///< label map: values are classes, filtered by mode not mean
    bool monochrome1 = false;     ///< DICOM MONOCHROME1: display with inverted grey scale
    bool spacingAssumed = false;      ///< the source gave no pixel spacing: 1 mm assumed, lengths are not mm
    bool orientationAssumed = false;  ///< the source gave no orientation: axial assumed, left/right unknown
    /// A CT whose values are not Hounsfield units (DICOM RescaleType other than HU: an iodine or
    /// effective-Z map): no HU windows, presets or padding; measured without units.
    bool notHounsfield = false;
    /// The source's own windows (DICOM WindowCenter/WindowWidth and their explanations), first
    /// the default; at most 4 are kept in an .hvo.
    std::vector<DisplayWindow> windows;

    /// The value CT pixels marked as padding (outside the scanned field) are given: air.
    static constexpr double kCtPaddingHu = -1024.0;
    /// Whether the values are Hounsfield units: a CT whose RescaleType is HU or absent.
    bool hounsfield() const { return modality == "CT" && !notHounsfield; }
    /// Whether `code` has the form of a DICOM modality code (2 to 8 capitals: CT, MR, PT, RTDOSE).
    static bool isModalityCode(const std::string& code);
    /// Number of voxels (as 64-bit, volumes may exceed 2^32 voxels).
    std::uint64_t voxelCount() const {
        return std::uint64_t(dims[0]) * dims[1] * dims[2];
    }
    /// Bytes of the uncompressed voxel data.
    std::uint64_t byteSize() const { return voxelCount() * scalarSize(scalarType); }
    /// 4×4 matrix mapping continuous voxel index (i, j, k, 1) to LPS millimetres.
    glm::dmat4 indexToPatient() const;
    /// The centre of the voxel nearest to a patient point (each index rounded, in or out of the
    /// grid): where a slice through it shows acquired voxels, not a blend of two layers.
    glm::dvec3 nearestVoxelCentre(const glm::dvec3& patient) const;
    /// A plane through `patient` with unit `normal`, moved along the normal onto the nearest
    /// layer of voxel centres when the grid has layers facing that way (a native axial of an
    /// axial acquisition): the slice shows acquired voxels, not a blend of two layers. Any other
    /// plane (a reformat) is returned where it is.
    glm::dvec3 onNearestLayer(const glm::dvec3& patient, const glm::dvec3& normal) const;
    /// How far from the patient coordinates' origin a voxel may lie (1 km, in mm).
    static constexpr double kMaxPatientMm = 1e6;
    /// Throws core::Error (prefixed by `what`) when dims, spacing or direction are unusable
    /// (a NaN, dependent axes) or a voxel lies more than kMaxPatientMm from the origin.
    void validate(const std::string& what) const;
    /// What makes `other` not the same grid with the same rescale ("dimensions 64x64x6, not
    /// 64x64x8"), empty when it is: voxels at the same patient points (within a thousandth of
    /// a voxel) whose stored values mean the same (the time points of one 4D series).
    std::string gridDifference(const VolumeGeometry& other) const;
};

}  // namespace hvx::core
