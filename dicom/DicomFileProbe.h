#pragma once
#include <cstdint>
#include <string>

namespace hvx::dicom {

/// The identifying header fields of one DICOM file, read without its pixel data.
/// DCMTK stays private: no DCMTK type appears here (DESIGN.md).
struct DicomFileProbe {
    std::string path;
    std::string sopClassUid;
    std::string transferSyntaxUid;
    std::string modality;
    std::string patientName;
    std::string patientId;
    std::string studyInstanceUid;
    std::string seriesInstanceUid;
    std::uint16_t rows = 0;
    std::uint16_t columns = 0;
    std::uint32_t frames = 0;

    /// Reads the header up to the pixel data. Throws core::Error naming the file and the reason
    /// (not DICOM, truncated, unreadable).
    static DicomFileProbe probe(const std::string& path);
    /// One line: file, modality, patient, size, transfer syntax.
    std::string summary() const;
    /// DCMTK's version string, e.g. "3.6.7".
    static std::string dcmtkVersion();
};

}  // namespace hvx::dicom
