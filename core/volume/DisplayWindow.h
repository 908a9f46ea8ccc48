#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hvx::core {

struct VolumeGeometry;

/// A grey-scale window in physical units (HU for CT): what the slice views show from black
/// (centre - width/2) to white (centre + width/2), with a name for menus and the view.
struct DisplayWindow {
    std::string name;
    double centre = 0.0;
    double width = 1.0;

    /// The usual CT windows, in the order of the number keys: brain, subdural, stroke, bone,
    /// lung, mediastinum, abdomen, liver (the values Horos, Weasis and radiology references use).
    static const std::vector<DisplayWindow>& ctPresets();
    /// What a volume opens with: the DICOM's first window; else for CT W 400 / L 40; else the
    /// 1st-99th percentile of its values when known (`percentiles`); else its value range.
    static DisplayWindow initial(const VolumeGeometry& g, std::optional<std::pair<double, double>> percentiles = {});
    /// The presets a volume offers, keys 1.. in order: the DICOM's own, then for CT ctPresets().
    static std::vector<DisplayWindow> presetsFor(const VolumeGeometry& g);
};

}  // namespace hvx::core
