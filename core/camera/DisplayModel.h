#pragma once
#include <string>
#include <vector>

#include "core/camera/View.h"
#include "core/camera/AccuracyFunction.h"

namespace hvx::core {

/// A multi-view display: a camera model (the views of one frame) plus an accuracy function
/// (DESIGN.md decisions 3-4), loaded from a JSON profile (resources/displays, embedded at build
/// time, or a file). Kinds:
///  - projector-array: a horizontal-parallax projector array behind an anisotropic screen
///    (HoloVizio); one Screen view per projector with MCOP rays (thesis Eq. 5.1) and
///    s(z) = s0 + 2|z| tan(phi/2);
///  - lenticular: a Looking Glass quilt of cols x rows off-axis views (shifted, never toed in)
///    spread over the view cone, view 0 the leftmost;
///  - stereo: two off-axis views (side by side, anaglyph, or 2-view column interleave).
///
/// Threading: a value type.
struct DisplayModel {
    enum class Kind { ProjectorArray, Lenticular, Stereo };
    enum class StereoLayout { SideBySide, Anaglyph, ColumnInterleave };

    std::string name;
    Kind kind = Kind::ProjectorArray;
    double screenWidthMm = 500, screenHeightMm = 375;
    double observerHeightMm = 0, observerDistanceMm = 1000;
    // projector-array
    int projectors = 0, projectorWidth = 0, projectorHeight = 0;
    double pixelSizeMm = 1.0;       ///< s0
    double beamAngleDegrees = 0.8;  ///< phi
    double fieldOfViewDegrees = 50;
    double projectorDistanceMm = 1000;
    // lenticular
    int quiltColumns = 0, quiltRows = 0, quiltWidth = 0, quiltHeight = 0;
    double aspect = 1.0, viewConeDegrees = 40;
    // stereo
    StereoLayout layout = StereoLayout::SideBySide;
    int viewWidth = 0, viewHeight = 0;
    double eyeSeparationMm = 63;

    /// A profile by name (the file name without .json, e.g. "holovizio-72") or a path to a
    /// JSON file. Throws core::Error naming the profile and the bad field.
    static DisplayModel load(const std::string& nameOrPath);
    static DisplayModel parse(const std::string& json, const std::string& what);
    /// Names of the built-in profiles.
    static std::vector<std::string> builtInNames();

    int viewCount() const;
    int viewWidthPx() const;
    int viewHeightPx() const;
    /// Display-space position of projector i (behind the screen, spread over the field of view).
    glm::dvec3 projectorPosition(int i) const;
    /// The views of one frame, the screen placed at `centre` with axes `right` and `up` in
    /// patient space (one display mm per patient mm). `eta` blends MCOP (1) towards one
    /// perspective (0) on projector arrays; sizes override the profile's view size when > 0.
    /// `scale`: display mm per patient mm (a 200 mm head on a 120 mm screen needs 0.5);
    /// `depthScale` the same along the screen's normal (0: `scale`), see Framing.
    std::vector<View> views(const glm::dvec3& centre, const glm::dvec3& right, const glm::dvec3& up, double eta = 1.0,
                            int widthOverride = 0, int heightOverride = 0, double scale = 1.0, double depthScale = 0.0) const;
    /// How a volume is placed on the display by default: its content's middle on the screen
    /// centre, as wide as the screen (or as tall, whichever is reached first; `scale`, display mm
    /// per patient mm across the screen), its depth within the range where s(z) stays within
    /// twice s(0) (depthRangeMm): `depthScale`, display mm per patient mm along the screen's
    /// normal, below `scale` where the depth had to be compressed, as a Looking Glass's
    /// "depthiness" does. With `trueDepth` both are one scale, the smaller (no distortion; the
    /// volume is then often much smaller than the screen). `points`: the content's corners (patient mm).
    struct Framing {
        glm::dvec3 centre{0.0};
        double scale = 1.0, depthScale = 1.0;
        const char* limit = "width";  ///< "width" or "height": what set `scale`
    };
    Framing frame(const std::vector<glm::dvec3>& points, const glm::dvec3& right, const glm::dvec3& up,
                  bool trueDepth = false) const;
    /// The depth range (display mm, either side of the screen) where s(z) <= 2 s(0).
    double depthRangeMm() const;
    /// s(z): the largest feature (display mm) the display can show at distance z from the screen.
    double accuracy(double zMm) const;
    /// The working set's accuracy function for these views (patient mm, from the screen plane).
    AccuracyFunction accuracyFunction(double scale = 1.0, double depthScale = 0.0) const;
};

}  // namespace hvx::core
