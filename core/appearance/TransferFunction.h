#pragma once
#include <array>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace hvx::core {

class LabelTable;
class ColorMap;

/// A 1D transfer function over stored values: piecewise-linear colour and opacity between
/// control points, sampled into a 4096-entry table over [valueMin, valueMax]. Colours are
/// extinction-weighted (thesis §3.2.2): opacity a per reference length d_ref becomes extinction
/// tau = -ln(1 - a) / d_ref, and k = tau * colour. The table keeps f = (k_r, k_g, k_b, tau) and
/// its running integral F, so a segment's average attributes follow Eq. 3.1 (pre-integration)
/// and "is [min, max] empty?" is F(max) - F(min) == 0, in O(1).
///
/// Threading: immutable after construction; share freely.
class TransferFunction {
public:
    struct Point {
        double value;        ///< stored (not rescaled) value
        glm::dvec4 rgba;     ///< colour and opacity per reference length, each in [0, 1]
    };
    static constexpr int kEntries = 4096;

    /// Builds the tables; points need not be sorted. referenceLength is d_ref (world mm).
    TransferFunction(std::vector<Point> points, double valueMin, double valueMax, double referenceLength = 1.0);
    /// A preset by name over a value range in physical units converted by (slope, intercept):
    /// ct-bone, ct-soft-tissue, ct-angio, ct-lung, ct-muscle, mr-default, mr-angio, mip-ramp.
    /// Throws core::Error.
    static TransferFunction preset(const std::string& name, double valueMin, double valueMax, double slope,
                                   double intercept, double referenceLength);
    static std::vector<std::string> presetNames();
    /// A label map's colours: one table entry per label value, from the table's smallest label
    /// on, so that entry(v) of label v is that label's colour and opacity exactly; labels the
    /// table lacks, hidden ones and label 0 are transparent. `opacity` scales every label's
    /// own. Throws core::Error when the labels span more than kEntries values.
    static TransferFunction forLabels(const LabelTable& table, double opacity, double referenceLength);
    /// A volume fused over another in 3D (PET over CT): below the window's low end (`low`,
    /// stored units) transparent, across the window the colour map's entries with opacity
    /// rising linearly to `opacity` at its high end, above it the last colour at `opacity`;
    /// over the volume's stored range [valueMin, valueMax]. `low` and `high` are the stored
    /// values of the window's physical low and high ends: under a negative rescale slope
    /// high < low, and the map runs down the stored values.
    static TransferFunction forColorMap(const ColorMap& map, double low, double high, double opacity, double valueMin,
                                        double valueMax, double referenceLength);

    double valueMin() const { return min_; }
    double valueMax() const { return max_; }
    double referenceLength() const { return refLength_; }
    /// f(s): (k_r, k_g, k_b, tau) at a value, linearly interpolated in the table.
    glm::dvec4 sample(double value) const;
    /// Eq. 3.1: the average of f over the segment from value a to value b.
    glm::dvec4 segment(double a, double b) const;
    /// segment(a, b).w alone (the extinction), in the same operations.
    double segmentExtinction(double a, double b) const;
    /// f at the table entry holding `value`, not interpolated: the classification of a label
    /// map, where a value between two entries belongs to one of them, never to a blend.
    glm::dvec4 entry(double value) const;
    /// True when no value in [lo, hi] has any opacity, nor a refraction index other than 1
    /// (the rays pass such values straight and see nothing: thesis §3.2.2's "empty" values).
    bool isEmpty(double lo, double hi) const;
    const std::vector<Point>& points() const { return points_; }
    /// The table f (kEntries values) and its running integral F (kEntries + 1), as the GPU
    /// uploads them.
    const std::vector<glm::dvec4>& table() const { return f_; }
    const std::vector<glm::dvec4>& integralTable() const { return F_; }

    /// Gradient opacity (MedVis §3.2.1, as VTK's and 3D Slicer's): a sample's opacity is scaled
    /// by a piecewise-linear curve over its gradient magnitude |∇f| (stored units per mm), as
    /// extinction: a' = 1 − (1 − a)^g(|∇f|), so homogeneous regions fade and boundaries stay.
    struct GradientPoint {
        double magnitude;  ///< |∇f|, stored units per mm
        double scale;      ///< [0, 1]
    };
    static constexpr int kGradientEntries = 256;
    /// Sets the curve (constant beyond its ends); an empty curve, or one that is 1 everywhere,
    /// switches it off (the image is then bitwise what it was). Throws core::Error for values
    /// that are not finite, negative magnitudes or scales outside [0, 1].
    void setGradientOpacity(std::vector<GradientPoint> points);
    bool hasGradientOpacity() const { return !gradientPoints_.empty(); }
    const std::vector<GradientPoint>& gradientOpacity() const { return gradientPoints_; }
    /// g(|∇f|) from the table, linearly interpolated as the shader reads it (1 when off).
    double gradientScale(double magnitude) const;
    /// The curve sampled at kGradientEntries magnitudes over [0, gradientMax()] (the GPU's table).
    const std::vector<float>& gradientTable() const { return gradientTable_; }
    double gradientMax() const { return gradientMax_; }

    /// Refraction (thesis §3.2.2, Figs 3.4–3.5): a refraction index ν(s) over stored values,
    /// piecewise linear between its points (constant beyond the ends), kept as its own
    /// pre-integrated table, so that a segment's index is its average over the values it spans
    /// (Eq. 3.1). With one, DVR rays bend at each step by Snell's law
    /// (core::glsl::hvxRefractStep). An empty curve, or one that is 1 everywhere, switches it
    /// off (the image is then bitwise what it was).
    struct RefractionPoint {
        double value;  ///< stored value
        double index;  ///< ν, [kMinRefraction, kMaxRefraction]
    };
    static constexpr double kMinRefraction = 0.25, kMaxRefraction = 4.0;
    /// Sets the curve; throws core::Error for values that are not finite or an index outside
    /// [kMinRefraction, kMaxRefraction].
    void setRefraction(std::vector<RefractionPoint> points);
    bool hasRefraction() const { return !refractionPoints_.empty(); }
    const std::vector<RefractionPoint>& refraction() const { return refractionPoints_; }
    /// The GPU's table: (∫(ν − 1) up to entry i, ν_i − 1) at kEntries + 1 entries (entry
    /// kEntries repeats the last ν); relative to 1, so that air's entries are exactly 0.
    const std::vector<glm::vec2>& refractionTable() const { return refractionTable_; }
    /// ν averaged over the segment from value a to value b (1 without a curve), in the float
    /// operations of resources/shaders/raycast_refract.glsl's tfSegmentRefraction.
    float refractionSegment(float a, float b) const;
    /// A curve that follows the opacity: ν(s) = 1 + (index − 1) · min(1, α(s) / 0.05) at every
    /// control point, so that what shows at all (from 5 % opacity per reference length) refracts
    /// with `index` and what shows nothing (air) does not; the Rendering dock's and the CLI's
    /// one-number refraction. Index 1: none.
    std::vector<RefractionPoint> refractionByOpacity(double index) const;

private:
    double position(double value) const;  // continuous table index
    glm::dvec4 integral(double value) const;

    std::vector<Point> points_;
    double min_, max_, refLength_;
    std::vector<glm::dvec4> f_;  // kEntries
    std::vector<glm::dvec4> F_;  // kEntries + 1, F_[i] = integral up to table position i
    std::vector<GradientPoint> gradientPoints_;
    std::vector<float> gradientTable_;
    double gradientMax_ = 1.0;
    std::vector<RefractionPoint> refractionPoints_;
    std::vector<glm::vec2> refractionTable_;
    std::vector<double> refractionDeviation_;  // kEntries + 1: running sum of |ν − 1| (isEmpty)
};

}  // namespace hvx::core
