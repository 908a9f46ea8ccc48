#pragma once
#include <string>
#include <vector>

#include "core/base/JobContext.h"
#include "core/volume/VoxelSource.h"

namespace hvx::dicom {

/// What to put in the DICOM objects that export a volume.
struct DicomWriteOptions {
    /// Who the images are of: empty (DICOM's "unknown") unless given; never made up.
    std::string patientName;
    std::string patientId;
    std::string patientBirthDate;
    std::string patientSex;
    /// What the export did to the images (Derivation Description, at most 1024 characters):
    /// the source's warnings, such as slices interpolated where the series had none.
    std::string derivation;
    std::string studyDescription = "Holovox export";
    std::string seriesDescription = "Volume";
    std::string studyDate;  ///< YYYYMMDD; today when empty
    std::string accessionNumber;
    std::string studyUid, seriesUid;  ///< generated when empty
    std::string frameOfReferenceUid;  ///< a DICOM source's, so the export registers with it; new when empty
    int seriesNumber = 1;
    /// From the volume when empty. CT and MR are written as CT and MR Image Storage; any other
    /// modality (PT, NM, OT...) as Secondary Capture, which claims no acquisition it cannot know.
    std::string modality;
    /// explicit-little (default), implicit-little, explicit-big, deflate, rle, jpeg-lossless,
    /// jpeg-ls
    std::string transferSyntax = "explicit-little";
    bool enhancedMultiframe = false;  ///< one Enhanced CT/MR object with per-frame groups
};

/// Writes a volume as a DICOM series (one file per k-slice, or one enhanced multi-frame
/// object), with exact ImagePositionPatient / ImageOrientationPatient / PixelSpacing from the
/// volume's geometry (a sheared geometry gives a tilted-gantry stack; rows and columns must be
/// perpendicular) and its rescale. The series is written into a folder beside the target and
/// renamed to it when whole, so a failed or cancelled export leaves nothing, and the target
/// must be new or empty, so an export never mixes with or replaces other files. 8-bit volumes
/// are widened to 16 bits for CT and MR, whose IODs allow no other. Holovox uses it to export,
/// to seed the demo archive, and to write test series with known geometry.
class DicomSeriesWriter {
public:
    /// Writes into `folder` (created if needed); returns the file paths in slice order.
    /// Throws core::Error (unsupported type or syntax, unwritable folder) or core::Cancelled.
    static std::vector<std::string> write(core::VoxelSource& source, const std::string& folder,
                                          const DicomWriteOptions& options, core::JobContext& job);
};

}  // namespace hvx::dicom
