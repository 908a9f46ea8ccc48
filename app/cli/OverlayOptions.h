#pragma once
#include <map>
#include <string>
#include <utility>

#include "core/appearance/ColorMap.h"
#include "core/volume/DisplayWindow.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::app {

/// "B.hvo[:lut=hot,opacity=0.5,window=W/L]" (slice and render --overlay): the path and its
/// options; throws core::Error naming an unknown option.
std::pair<std::string, std::map<std::string, std::string>> overlaySpec(const std::string& text);

/// An overlay's colour map (lut=, default hot), window (window=W/L in physical units, default
/// the volume's initial window) and opacity (opacity=, default 0.5); throws core::Error.
struct OverlayLook {
    core::ColorMap map;
    core::DisplayWindow window;
    double opacity = 0.5;
};
OverlayLook overlayLook(const std::map<std::string, std::string>& opts, const core::VolumeGeometry& g);

/// Refuses a partner in another frame of reference unless forced; prints the note otherwise.
void pairFrames(const core::VolumeGeometry& base, const std::string& baseName, const core::VolumeGeometry& partner,
                const std::string& partnerName, bool force);

}  // namespace hvx::app
