#pragma once
#include <string>

#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// Whether a second volume may be laid over a first by their patient coordinates (fusion, a
/// label map over its image): refused when both name a DICOM Frame of Reference and the two
/// differ (their LPS axes are not the same axes), or when either volume's orientation was
/// assumed (its left and right are not known); a note when a frame is not known.
struct FramePairing {
    bool refused = false;
    std::string sentence;  ///< why refused, or a note to show; empty when the frames match

    /// `baseName` and `partnerName` name the volumes in the sentence.
    static FramePairing of(const VolumeGeometry& base, const std::string& baseName, const VolumeGeometry& partner,
                           const std::string& partnerName);
};

}  // namespace hvx::core
