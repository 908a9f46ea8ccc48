#pragma once
#include <string>

#include "dicom/DicomInstance.h"

namespace hvx::dicom {

/// Reads a DICOM file's header (stopping before the pixel data) into a DicomInstance.
class DicomHeaderReader {
public:
    /// Outcome for files that are not DICOM at all, as opposed to broken DICOM files.
    enum class Kind { Dicom, NotDicom };
    /// Reads `path`. Returns Kind::NotDicom for files without a DICOM preamble or meta header
    /// that DCMTK cannot parse either; throws core::Error naming the file for broken DICOM.
    static Kind read(const std::string& path, DicomInstance& out);
};

}  // namespace hvx::dicom
