#pragma once
#include <cstdint>
#include <vector>

#include "core/appearance/ColorMap.h"
#include "core/appearance/LabelTable.h"
#include "core/reference/SliceSampler.h"
#include "core/volume/DisplayWindow.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::core {

/// A second volume laid over a slice (PET over CT): sampled on the base's plane, coloured by
/// its own map through its own window, blended with `opacity`. Values that take the map's first
/// entry (at or near the window's low end) are not drawn, as in mricron, so that the anatomy
/// stays readable where the overlay has nothing.
struct SliceOverlay {
    const SliceImage* image = nullptr;
    const VolumeGeometry* geometry = nullptr;  ///< the overlay's, for its rescale
    ColorMap map = ColorMap::named("hot");
    DisplayWindow window;
    double opacity = 0.5;
};

/// A label map laid over a slice: each label's colour as fill (blended with `opacity` times the
/// label's own alpha) and/or outline (the label's border pixels at the label's own alpha).
struct SliceLabels {
    const SliceImage* image = nullptr;  ///< sampled nearest (SliceSampler does for label maps)
    const LabelTable* table = nullptr;
    double opacity = 0.5;
    bool fill = true;
    bool outline = true;
};

/// Turns sampled slices into what the reader sees: the base in grey through its window
/// (MONOCHROME1 inverted, black outside the volume), then the overlay, then the labels.
///
/// Threading: pure functions.
class SliceComposer {
public:
    /// 8-bit grey, one byte per pixel, rows from the top.
    static std::vector<std::uint8_t> grey(const SliceImage& base, const VolumeGeometry& g, const DisplayWindow& w);
    /// 8-bit RGB, three bytes per pixel, rows from the top. `overlay` and `labels` may be null;
    /// their images must have the base's size (core::Error otherwise).
    static std::vector<std::uint8_t> compose(const SliceImage& base, const VolumeGeometry& g, const DisplayWindow& w,
                                             const SliceOverlay* overlay, const SliceLabels* labels);
    /// The labels (non-zero) a label slice shows, ascending.
    static std::vector<int> labelsIn(const SliceImage& labels);
};

}  // namespace hvx::core
