#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/volume/FileElement.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// A NIfTI-1 header (the 348 bytes at the start of a .nii or .nii.gz), read and turned into a
/// Holovox geometry. The placement follows nibabel, FSL and SPM: the sform when sform_code > 0,
/// else the qform when qform_code > 0 (quaternion, pixdim and qfac = pixdim[0], 0 taken as 1),
/// else pixdim alone with a warning that left and right are unknown. NIfTI's RAS+ millimetres
/// become LPS (x and y negated); xyzt_units scales metres and micrometres to millimetres; a
/// sheared sform is kept as it is. Voxels stay in file order (i fastest), so a negative qfac or
/// a flipped sform is only a direction, never a reordering of slices.
///
/// Threading: a value type.
struct NiftiHeader {
    /// NIfTI datatype codes (nifti1.h).
    enum DataType : std::int16_t {
        Uint8 = 2, Int16 = 4, Int32 = 8, Float32 = 16, Float64 = 64, Int8 = 256, Uint16 = 512, Uint32 = 768,
        Int64 = 1024, Uint64 = 1280
    };

    VolumeGeometry geometry;            ///< placement, stored type and rescale of one 3D volume
    std::int16_t dataType = 0;          ///< the file's datatype code
    FileElement element = FileElement::UInt8;  ///< the file's element type (kept as geometry.scalarType)
    bool bigEndian = false;             ///< the file's byte order (from sizeof_hdr)
    std::uint64_t voxOffset = 352;      ///< byte offset of the voxel data
    std::uint32_t volumes = 1;          ///< dim[4]: 3D volumes in the file (time points)
    std::vector<std::string> warnings;  ///< sentences about what was assumed or disagrees
    /// RAS+ millimetre affines of the two placements (identity when their code is 0).
    glm::dmat4 qform{1.0}, sform{1.0};
    /// The codes as placed: a qform that cannot place the volume (a zero pixdim, a qfac other
    /// than ±1) beside a usable sform counts as 0, with a warning.
    int qformCode = 0, sformCode = 0;

    /// Parses the first 348 bytes of a NIfTI-1 file; `what` names it in messages. Throws
    /// core::Error with a sentence for anything that cannot be placed or read exactly (NIfTI-2,
    /// vector or complex data, a zero or negative dimension, an unusable placement).
    static NiftiHeader parse(const unsigned char* bytes, std::size_t size, const std::string& what);
    /// The qform's index-to-RAS affine from its quaternion, offsets, pixdim and qfac.
    static glm::dmat4 quaternionAffine(double b, double c, double d, const glm::dvec3& offset,
                                       const glm::dvec3& pixdim, double qfac);
};

}  // namespace hvx::core
