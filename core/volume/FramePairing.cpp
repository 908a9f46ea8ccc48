#include "core/volume/FramePairing.h"

namespace hvx::core {

FramePairing FramePairing::of(const VolumeGeometry& base, const std::string& baseName, const VolumeGeometry& partner,
                              const std::string& partnerName) {
    if (base.orientationAssumed || partner.orientationAssumed)
        return {true, (base.orientationAssumed ? baseName : partnerName) +
                          " has no known orientation (axial was assumed): laid over the other, left could land on "
                          "right"};
    const auto& a = base.frameOfReferenceUid;
    const auto& b = partner.frameOfReferenceUid;
    if (!a.empty() && !b.empty() && a != b)
        return {true, baseName + " and " + partnerName + " lie in different frames of reference (" + a + " and " + b +
                          "): their patient coordinates are not the same axes; register them first"};
    if (a.empty() && b.empty())
        return {false, "the frames of reference of " + baseName + " and " + partnerName +
                           " are not known: the two are aligned by their patient coordinates (LPS) alone"};
    if (a.empty() || b.empty())
        return {false, "the frame of reference of " + (a.empty() ? baseName : partnerName) +
                           " is not known: the two are aligned by their patient coordinates (LPS) alone"};
    return {};
}

}  // namespace hvx::core
