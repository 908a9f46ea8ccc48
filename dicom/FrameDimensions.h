#pragma once
#include <optional>
#include <string>

#include <glm/vec3.hpp>

namespace hvx::dicom {

/// What tells apart the images a series holds at one position: the echo of a multi-echo
/// acquisition, the b-value and gradient of a diffusion series, the time point of a dynamic or
/// cardiac series, the acquisition, the image type (magnitude, phase, ...) and the enhanced
/// stack. Read per frame from the classic attributes or the enhanced functional groups; an
/// attribute the file does not carry stays empty.
struct FrameDimensions {
    std::string imageType;  ///< ImageType, or FrameType of an enhanced frame
    std::optional<int> echoNumber;
    std::optional<double> echoTime;  ///< ms: EchoTime or EffectiveEchoTime
    std::optional<double> bValue;    ///< s/mm²: DiffusionBValue
    std::optional<glm::dvec3> gradient;  ///< DiffusionGradientOrientation
    std::optional<int> temporalPosition;  ///< TemporalPositionIdentifier or TemporalPositionIndex
    std::optional<double> triggerTime;    ///< ms: TriggerTime or NominalCardiacTriggerDelayTime
    std::optional<int> acquisitionNumber;
    std::string stackId;  ///< enhanced StackID
};

}  // namespace hvx::dicom
