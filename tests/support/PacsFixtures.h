#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "dicom/DicomSeriesWriter.h"

namespace hvx::test {

/// Two patients' studies written as DICOM for the PACS tests: study A (DOE^JANE, CT, 20240301)
/// with series A1 (20 images) and A2 (10), study B (ROE^RICHARD, MR, 20231115) with B1 (8).
struct Seeded {
    std::string studyA, studyB, seriesA1, seriesA2, seriesB1;
    std::vector<std::string> files;
};

/// A phantom volume written as a DICOM series with these options.
std::vector<std::string> writeSeries(const std::string& dir, std::array<std::uint32_t, 3> dims,
                                     dicom::DicomWriteOptions o);
/// Writes the studies of Seeded under `dir`.
Seeded makeStudies(const std::string& dir);
/// The dataset part of a DICOM file (after the File Meta Information), which a transfer keeps.
std::string datasetBytes(const std::string& path);
/// The files by their SOP Instance UID.
std::map<std::string, std::string> bySop(const std::vector<std::string>& files);

}  // namespace hvx::test
