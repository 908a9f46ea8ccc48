#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dicom/DicomInstance.h"

namespace hvx::dicom {

/// Splits the frames of one stack (one series, one geometry) into volumes when several images
/// share a position, as dcm2niix and 3D Slicer's multi-volume importer do: by image type
/// (magnitude, phase, ...), echo (number and TE), diffusion b-value and gradient, temporal
/// position, trigger time, acquisition number or enhanced stack: the first that tells images at
/// one position apart without leaving a part of less than half the positions, else the first
/// that tells some apart, and so on where positions still repeat. Positions closer than a
/// twentieth of the stack's mean spacing count as one. A part whose
/// images still share a position cannot be told apart: it is refused, never mixed and never
/// reduced to "the first". Images at distinct but unevenly spaced positions that one of those
/// dimensions divides into evenly spaced, overlapping parts closer than one interleaved grid's
/// (two acquisitions offset a little) are split too, rather than interleaved and interpolated. Images without positions are split
/// by image type, echo, diffusion or time point where one varies (nothing else is known).
///
/// Threading: pure functions.
class VolumeSplitter {
public:
    /// A frame of the stack: instance index and frame number.
    using Member = std::pair<std::size_t, std::uint32_t>;
    struct Part {
        std::vector<Member> members;
        std::string varying;  ///< what tells it from its siblings, e.g. "echo 2 (TE 20 ms)"; empty when alone
    };
    struct Result {
        std::vector<Part> parts;
        std::vector<std::string> refused;  ///< one sentence per part refused
    };
    /// `normal`: the stack's slice normal, along which positions are compared (to 1 µm).
    static Result split(const std::vector<DicomInstance>& instances, const std::vector<Member>& members,
                        const glm::dvec3& normal);
};

}  // namespace hvx::dicom
