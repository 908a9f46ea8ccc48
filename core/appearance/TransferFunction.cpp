#include "core/appearance/TransferFunction.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/common.hpp>

#include "core/appearance/ColorMap.h"
#include "core/appearance/LabelTable.h"
#include "core/base/Error.h"

namespace hvx::core {

TransferFunction::TransferFunction(std::vector<Point> points, double valueMin, double valueMax, double referenceLength)
    : points_(std::move(points)), min_(valueMin), max_(valueMax), refLength_(referenceLength) {
    if (points_.empty()) throw Error("a transfer function needs at least one control point");
    if (!(max_ > min_)) max_ = min_ + 1.0;
    if (!(refLength_ > 0)) throw Error("transfer function reference length must be positive");
    std::sort(points_.begin(), points_.end(), [](const Point& a, const Point& b) { return a.value < b.value; });
    f_.resize(kEntries);
    for (int i = 0; i < kEntries; ++i) {
        const double v = min_ + (max_ - min_) * (i + 0.5) / kEntries;
        glm::dvec4 c;
        if (v <= points_.front().value) c = points_.front().rgba;
        else if (v >= points_.back().value) c = points_.back().rgba;
        else {
            auto hi = std::upper_bound(points_.begin(), points_.end(), v,
                                       [](double x, const Point& p) { return x < p.value; });
            auto lo = hi - 1;
            const double t = hi->value > lo->value ? (v - lo->value) / (hi->value - lo->value) : 0.0;
            c = lo->rgba + (hi->rgba - lo->rgba) * t;
        }
        const double a = std::clamp(c.a, 0.0, 0.999999);
        const double tau = -std::log(1.0 - a) / refLength_;
        f_[std::size_t(i)] = glm::dvec4(glm::dvec3(c) * tau, tau);
    }
    F_.assign(kEntries + 1, glm::dvec4(0.0));
    for (int i = 0; i < kEntries; ++i) F_[std::size_t(i) + 1] = F_[std::size_t(i)] + f_[std::size_t(i)];
}

double TransferFunction::position(double value) const {
    return std::clamp((value - min_) / (max_ - min_) * kEntries, 0.0, double(kEntries));
}

glm::dvec4 TransferFunction::sample(double value) const {
    const double p = std::clamp(position(value) - 0.5, 0.0, double(kEntries - 1));
    const auto i = std::size_t(p);
    const std::size_t j = std::min<std::size_t>(i + 1, kEntries - 1);
    const double t = p - double(i);
    return f_[i] * (1.0 - t) + f_[j] * t;
}

glm::dvec4 TransferFunction::entry(double value) const {
    return f_[std::min<std::size_t>(std::size_t(position(value)), kEntries - 1)];
}

TransferFunction TransferFunction::forLabels(const LabelTable& table, double opacity, double referenceLength) {
    const auto& entries = table.entries();
    const int lo = entries.empty() ? 0 : std::min(0, entries.begin()->first);
    const int hi = entries.empty() ? 0 : entries.rbegin()->first;
    if (hi - lo >= kEntries)
        throw Error("labels " + std::to_string(lo) + " to " + std::to_string(hi) + " span more than " +
                    std::to_string(kEntries) + " values: the 3D view colours at most that many consecutive labels");
    // Entry i is centred on value lo + i (the range starts half a value below lo), and a
    // control point sits on every integer: each entry is its label's colour, with no ramp.
    std::vector<Point> points;
    points.reserve(std::size_t(hi - lo + 1));
    for (int v = lo; v <= hi; ++v) {
        const auto* e = table.find(v);
        if (!e || !e->visible) {
            points.push_back({double(v), glm::dvec4(0.0)});
            continue;
        }
        points.push_back({double(v), glm::dvec4(e->rgba[0] / 255.0, e->rgba[1] / 255.0, e->rgba[2] / 255.0,
                                                std::clamp(opacity, 0.0, 1.0) * e->rgba[3] / 255.0)});
    }
    points.push_back({double(hi + 1), glm::dvec4(0.0)});  // values above the last label show nothing
    return TransferFunction(std::move(points), lo - 0.5, lo - 0.5 + kEntries, referenceLength);
}

void TransferFunction::setGradientOpacity(std::vector<GradientPoint> points) {
    for (const auto& p : points)
        if (!std::isfinite(p.magnitude) || !std::isfinite(p.scale) || p.magnitude < 0 || p.scale < 0 || p.scale > 1)
            throw Error("a gradient opacity point needs a magnitude of 0 or more and a scale of 0 to 1");
    std::sort(points.begin(), points.end(), [](const GradientPoint& a, const GradientPoint& b) { return a.magnitude < b.magnitude; });
    const bool flat = std::all_of(points.begin(), points.end(), [](const GradientPoint& p) { return p.scale == 1.0; });
    gradientPoints_.clear();
    gradientTable_.clear();
    gradientMax_ = 1.0;
    if (points.empty() || flat) return;  // off: nothing scaled, bitwise the plain image
    gradientPoints_ = std::move(points);
    gradientMax_ = std::max(gradientPoints_.back().magnitude, 1e-9);
    gradientTable_.resize(kGradientEntries);
    for (int i = 0; i < kGradientEntries; ++i) {
        const double m = gradientMax_ * i / (kGradientEntries - 1);
        double g = gradientPoints_.front().scale;
        for (std::size_t k = 1; k < gradientPoints_.size(); ++k) {
            const auto &a = gradientPoints_[k - 1], &b = gradientPoints_[k];
            if (m >= a.magnitude) g = b.magnitude > a.magnitude ? a.scale + (b.scale - a.scale) * std::min(1.0, (m - a.magnitude) / (b.magnitude - a.magnitude)) : b.scale;
        }
        gradientTable_[std::size_t(i)] = float(g);
    }
}

double TransferFunction::gradientScale(double magnitude) const {
    if (gradientTable_.empty()) return 1.0;
    const float p = std::clamp(float(magnitude / gradientMax_) * float(kGradientEntries - 1), 0.0f, float(kGradientEntries - 1));
    const int i = std::min(int(p), kGradientEntries - 2);
    const float f = p - float(i);
    return double(gradientTable_[std::size_t(i)] * (1.0f - f) + gradientTable_[std::size_t(i) + 1] * f);
}

TransferFunction TransferFunction::forColorMap(const ColorMap& map, double low, double high, double opacity,
                                               double valueMin, double valueMax, double referenceLength) {
    if (!(high != low) || !std::isfinite(low) || !std::isfinite(high))
        throw Error("a colour map's window needs a width above 0");
    if (!(opacity >= 0 && opacity <= 1)) throw Error("an overlay's opacity must be 0 to 1");
    // One control point per colour-map entry across the window, transparent beyond its low end;
    // a decreasing rescale (high < low in stored units) lays the entries in reverse.
    const auto& entries = map.entries();
    const auto& last = entries.back();
    const double width = std::abs(high - low);
    const glm::dvec4 top(last[0] / 255.0, last[1] / 255.0, last[2] / 255.0, opacity);
    std::vector<Point> points;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const double t = double(i) / double(entries.size() - 1);
        const auto& c = entries[i];
        points.push_back({low + t * (high - low), glm::dvec4(c[0] / 255.0, c[1] / 255.0, c[2] / 255.0, t * opacity)});
    }
    if (high > low) {
        points.insert(points.begin(), {std::min(low, valueMin) - width, glm::dvec4(0.0)});
        points.push_back({std::max(high, valueMax) + width, top});
    } else {
        std::reverse(points.begin(), points.end());
        points.insert(points.begin(), {std::min(high, valueMin) - width, top});
        points.push_back({std::max(low, valueMax) + width, glm::dvec4(0.0)});
    }
    return TransferFunction(std::move(points), valueMin, valueMax, referenceLength);
}

glm::dvec4 TransferFunction::integral(double value) const {
    const double p = position(value);
    const auto i = std::min<std::size_t>(std::size_t(p), kEntries - 1);
    return F_[i] + f_[i] * (p - double(i));
}

glm::dvec4 TransferFunction::segment(double a, double b) const {
    const double pa = position(a), pb = position(b);
    if (std::abs(pb - pa) > 1e-3) return (integral(b) - integral(a)) / (pb - pa);
    return sample(0.5 * (a + b));
}

double TransferFunction::segmentExtinction(double a, double b) const {
    const double pa = position(a), pb = position(b);
    auto integralW = [&](double p) {
        const auto i = std::min<std::size_t>(std::size_t(p), kEntries - 1);
        return F_[i].w + f_[i].w * (p - double(i));
    };
    if (std::abs(pb - pa) > 1e-3) return (integralW(pb) - integralW(pa)) / (pb - pa);
    const double p = std::clamp(position(0.5 * (a + b)) - 0.5, 0.0, double(kEntries - 1));
    const auto i = std::size_t(p);
    const std::size_t j = std::min<std::size_t>(i + 1, kEntries - 1);
    const double t = p - double(i);
    return f_[i].w * (1.0 - t) + f_[j].w * t;
}

bool TransferFunction::isEmpty(double lo, double hi) const {
    // Table bins touched by [lo, hi]; their summed extinction is zero only if all are.
    const auto a = std::size_t(std::clamp(position(lo), 0.0, double(kEntries - 1)));
    const auto b = std::size_t(std::clamp(position(hi), 0.0, double(kEntries - 1)));
    if (!refractionDeviation_.empty() && refractionDeviation_[b + 1] - refractionDeviation_[a] > 0.0) return false;
    return F_[b + 1].w - F_[a].w <= 0.0;
}

namespace {
std::string refractionRangeMessage(double index) {
    char text[160];
    std::snprintf(text, sizeof text, "a refraction index must be between %g and %g (got %g)", TransferFunction::kMinRefraction,
                  TransferFunction::kMaxRefraction, index);
    return text;
}
}  // namespace

void TransferFunction::setRefraction(std::vector<RefractionPoint> points) {
    for (const auto& p : points)
        if (!std::isfinite(p.value) || !(p.index >= kMinRefraction && p.index <= kMaxRefraction))
            throw Error(refractionRangeMessage(p.index));
    std::stable_sort(points.begin(), points.end(), [](const RefractionPoint& a, const RefractionPoint& b) { return a.value < b.value; });
    refractionPoints_.clear();
    refractionTable_.clear();
    refractionDeviation_.clear();
    if (std::all_of(points.begin(), points.end(), [](const RefractionPoint& p) { return p.index == 1.0; })) return;
    refractionPoints_ = std::move(points);
    refractionTable_.assign(kEntries + 1, glm::vec2(0.0f));
    refractionDeviation_.assign(kEntries + 1, 0.0);
    double integral = 0.0;
    for (int i = 0; i < kEntries; ++i) {
        const double v = min_ + (max_ - min_) * (i + 0.5) / kEntries;
        const auto& pts = refractionPoints_;
        double nu = pts.front().index;
        if (v >= pts.back().value) nu = pts.back().index;
        else if (v > pts.front().value) {
            const auto hi = std::upper_bound(pts.begin(), pts.end(), v, [](double x, const RefractionPoint& p) { return x < p.value; });
            const auto lo = hi - 1;
            nu = hi->value > lo->value ? lo->index + (hi->index - lo->index) * (v - lo->value) / (hi->value - lo->value) : hi->index;
        }
        refractionTable_[std::size_t(i)] = glm::vec2(float(integral), float(nu - 1.0));
        integral += nu - 1.0;
        refractionDeviation_[std::size_t(i) + 1] = refractionDeviation_[std::size_t(i)] + std::abs(nu - 1.0);
    }
    refractionTable_[kEntries] = glm::vec2(float(integral), refractionTable_[kEntries - 1].y);
}

float TransferFunction::refractionSegment(float a, float b) const {
    if (refractionTable_.empty()) return 1.0f;
    const float lo = float(min_), hi = float(max_);
    auto position = [&](float v) { return std::clamp((v - lo) / (hi - lo) * 4096.0f, 0.0f, 4096.0f); };
    auto integralAt = [&](float p) {
        const int i = std::min(int(p), kEntries - 1);
        const glm::vec2 e = refractionTable_[std::size_t(i)];
        return e.x + e.y * (p - float(i));
    };
    const float pa = position(a), pb = position(b);
    // Across more than one entry the integrals' difference; within one, where that difference
    // would be float rounding over a short span, the midpoint's index.
    if (std::abs(pb - pa) > 1.0f) return 1.0f + (integralAt(pb) - integralAt(pa)) / (pb - pa);
    const float p = std::clamp(position(0.5f * (a + b)) - 0.5f, 0.0f, 4095.0f);
    const int i = int(p);
    const int j = std::min(i + 1, kEntries - 1);
    return 1.0f + glm::mix(refractionTable_[std::size_t(i)].y, refractionTable_[std::size_t(j)].y, p - float(i));
}

std::vector<TransferFunction::RefractionPoint> TransferFunction::refractionByOpacity(double index) const {
    if (!(index >= kMinRefraction && index <= kMaxRefraction))
        throw Error(refractionRangeMessage(index));
    std::vector<RefractionPoint> out;
    if (index == 1.0) return out;
    for (const auto& p : points_) out.push_back({p.value, 1.0 + (index - 1.0) * std::min(1.0, p.rgba.a / 0.05)});
    return out;
}

std::vector<std::string> TransferFunction::presetNames() {
    return {"ct-bone", "ct-soft-tissue", "ct-angio", "ct-lung", "ct-muscle", "mr-default", "mr-angio", "mip-ramp"};
}

TransferFunction TransferFunction::preset(const std::string& name, double valueMin, double valueMax, double slope,
                                          double intercept, double referenceLength) {
    // Control points in physical units (HU for CT), converted to stored values.
    std::vector<Point> pts;
    auto add = [&](double physical, double r, double g, double b, double a) {
        pts.push_back({(physical - intercept) / slope, {r, g, b, a}});
    };
    if (name == "ct-bone") {
        add(-1024, 0, 0, 0, 0);
        add(150, 0.55, 0.25, 0.15, 0);
        add(300, 0.9, 0.8, 0.7, 0.35);
        add(1500, 1.0, 1.0, 0.95, 0.9);
    } else if (name == "ct-soft-tissue") {
        add(-1024, 0, 0, 0, 0);
        add(-200, 0.6, 0.3, 0.2, 0);
        add(-50, 0.8, 0.55, 0.45, 0.04);
        add(100, 0.9, 0.6, 0.5, 0.12);
        add(250, 1.0, 0.85, 0.75, 0.5);
        add(1500, 1.0, 1.0, 0.95, 0.9);
    } else if (name == "ct-angio") {
        add(-1024, 0, 0, 0, 0);
        add(120, 0.7, 0.1, 0.05, 0);
        add(220, 0.95, 0.3, 0.2, 0.45);
        add(400, 1.0, 0.9, 0.8, 0.8);
    } else if (name == "ct-lung") {
        add(-1024, 0, 0, 0, 0);
        add(-950, 0.3, 0.4, 0.7, 0);
        add(-800, 0.6, 0.7, 0.9, 0.08);
        add(-500, 0.9, 0.9, 1.0, 0.2);
        add(-200, 0.9, 0.6, 0.5, 0);
    } else if (name == "ct-muscle") {
        add(-1024, 0, 0, 0, 0);
        add(-155, 0.55, 0.25, 0.15, 0);
        add(217, 0.88, 0.6, 0.29, 0.68);
        add(420, 1.0, 0.94, 0.95, 0.83);
        add(1500, 0.83, 0.66, 1.0, 0.8);
    } else if (name == "mr-angio") {  // bright flow on a dark background (TOF / contrast MRA)
        const double span = (valueMax - valueMin) * slope;
        const double lo = valueMin * slope + intercept;
        add(lo, 0, 0, 0, 0);
        add(lo + 0.3 * span, 0.6, 0.1, 0.05, 0);
        add(lo + 0.5 * span, 0.95, 0.35, 0.25, 0.5);
        add(lo + span, 1, 0.95, 0.9, 0.9);
    } else if (name == "mr-default") {
        const double span = (valueMax - valueMin) * slope;
        const double lo = valueMin * slope + intercept;
        add(lo, 0, 0, 0, 0);
        add(lo + 0.2 * span, 0.5, 0.35, 0.3, 0);
        add(lo + 0.4 * span, 0.85, 0.7, 0.6, 0.15);
        add(lo + 0.7 * span, 1.0, 0.95, 0.9, 0.6);
        add(lo + span, 1, 1, 1, 0.9);
    } else if (name == "mip-ramp") {
        add(valueMin * slope + intercept, 0, 0, 0, 0);
        add(valueMax * slope + intercept, 1, 1, 1, 1);
    } else {
        std::string known;
        for (const auto& n : presetNames()) known += (known.empty() ? "" : ", ") + n;
        throw Error("unknown transfer function preset '" + name + "' (" + known + ")");
    }
    return TransferFunction(std::move(pts), valueMin, valueMax, referenceLength);
}

}  // namespace hvx::core
