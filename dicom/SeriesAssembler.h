#pragma once
#include <string>
#include <vector>

#include "dicom/SeriesVolume.h"

namespace hvx::dicom {

/// Turns scanned instances into volumes: groups by SeriesInstanceUID and then by geometry
/// (orientation, rows and columns, pixel spacing, pixel format), so a series holding a scout
/// and an axial stack gives two volumes; sorts each group by ImagePositionPatient projected on
/// the slice normal (never by InstanceNumber); derives spacing from the positions; and warns
/// about non-uniform spacing, missing slices, gantry tilt and mixed sizes. Images that share a
/// position are split into the volumes of a 4D series by what varies between them
/// (VolumeSplitter: echo, diffusion, time, ...), or refused with a note, never mixed.
///
/// Gantry tilt: the stack is kept sheared, with the exact (non-orthogonal) index-to-patient
/// transform stored in the geometry; no resampling blurs it.
class SeriesAssembler {
public:
    /// Assembles every image series found in `instances`. Objects that cannot form a volume
    /// (SR, RT plans, waveforms, presentation states, colour images) are listed in `notes`.
    static std::vector<SeriesVolume> assemble(const std::vector<DicomInstance>& instances,
                                              std::vector<std::string>& notes);
};

}  // namespace hvx::dicom
