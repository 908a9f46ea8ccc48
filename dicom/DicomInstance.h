#pragma once
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/volume/DisplayWindow.h"
#include "dicom/FrameDimensions.h"

namespace hvx::dicom {

/// Plane geometry and value transform of one frame (a single-frame image, or one frame of an
/// enhanced multi-frame object from its per-frame or shared functional groups).
struct FrameGeometry {
    bool hasPosition = false;
    glm::dvec3 position{0.0};  ///< ImagePositionPatient: LPS mm of the first pixel's centre
    bool hasOrientation = false;
    glm::dvec3 rowDirection{1, 0, 0};     ///< ImageOrientationPatient[0..2]: towards increasing column
    glm::dvec3 columnDirection{0, 1, 0};  ///< ImageOrientationPatient[3..5]: towards increasing row
    bool hasSpacing = false;
    glm::dvec2 pixelSpacing{1.0, 1.0};  ///< PixelSpacing: (between rows, between columns) mm
    double rescaleSlope = 1.0;
    double rescaleIntercept = 0.0;
    /// RescaleType as written (empty when absent): a CT's values are HU unless it names other
    /// units (US, MGML, Z_EFF, ... for dual-energy maps).
    std::string rescaleType;
    FrameDimensions dimensions;  ///< what tells this frame apart from others at its position
};

/// What the scanner reads from one DICOM file's header: the identifiers the study database
/// needs and everything series assembly and pixel decoding need. No DCMTK types.
struct DicomInstance {
    std::string path;
    std::string sopClassUid, sopInstanceUid, transferSyntaxUid;
    std::string patientName, patientId, patientBirthDate, patientSex;
    std::string studyInstanceUid, studyDate, studyTime, studyDescription, accessionNumber;
    std::string seriesInstanceUid, modality, seriesDescription, bodyPartExamined;
    std::string frameOfReferenceUid;
    /// A segmentation or structure set: the image series it was drawn on (SEG's Referenced
    /// Series Sequence, RTSTRUCT's RT Referenced Series Sequence); empty otherwise.
    std::string referencedSeriesUid;
    int seriesNumber = 0;
    int instanceNumber = 0;
    std::uint16_t rows = 0, columns = 0, samplesPerPixel = 1;
    std::uint16_t bitsAllocated = 0, bitsStored = 0, highBit = 0, pixelRepresentation = 0;
    std::uint32_t frames = 0;  ///< 0 for objects without pixel data
    /// 32 for Float Pixel Data, 64 for Double Float Pixel Data (decoded as float bits in the
    /// int32 samples, see PixelDecoder); 0 for integer Pixel Data.
    int floatPixelBits = 0;
    std::string photometric;
    std::optional<double> pixelPadding;
    /// Pixel Padding Range Limit: with it, every stored value between it and pixelPadding
    /// (inclusive) is padding.
    std::optional<double> pixelPaddingLimit;
    /// The stored values that are padding (outside the scanned field, not measurements), as
    /// [low, high]; an empty range (low > high) when the image has none. Worked out once per
    /// image, not per pixel.
    std::pair<double, double> paddingRange() const {
        if (!pixelPadding) return {1.0, 0.0};
        const double limit = pixelPaddingLimit.value_or(*pixelPadding);
        return {std::min(*pixelPadding, limit), std::max(*pixelPadding, limit)};
    }
    double sliceThickness = 0.0;
    /// WindowCenter/WindowWidth pairs (physical units) with their explanations, first the default.
    std::vector<core::DisplayWindow> windows;
    std::uint64_t fileSize = 0;
    /// Geometry per frame (one entry for single-frame images).
    std::vector<FrameGeometry> frameGeometry;

    /// Frame f's geometry (frame 0's where the object states one for all; frameGeometry not empty).
    const FrameGeometry& frame(std::size_t f) const { return frameGeometry[std::min(f, frameGeometry.size() - 1)]; }

    /// True for objects with image pixel data that can form volumes.
    bool hasPixels() const { return rows > 0 && columns > 0 && frames > 0 && bitsAllocated > 0; }
};

}  // namespace hvx::dicom
