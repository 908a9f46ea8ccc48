#include "core/appearance/TransferFunctionSpec.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <glm/vector_relational.hpp>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
template <class P, class V>
V interpolate(const std::vector<P>& pts, double value, V P::*field) {
    if (pts.empty()) return V{};
    if (value <= pts.front().value) return pts.front().*field;
    if (value >= pts.back().value) return pts.back().*field;
    const auto hi = std::upper_bound(pts.begin(), pts.end(), value, [](double v, const P& p) { return v < p.value; });
    const auto lo = hi - 1;
    const double span = hi->value - lo->value;
    const double t = span > 0 ? (value - lo->value) / span : 0.0;
    return (*lo).*field + ((*hi).*field - (*lo).*field) * t;
}
}  // namespace

TransferFunctionSpec TransferFunctionSpec::from(const TransferFunction& tf) {
    TransferFunctionSpec s;
    for (const auto& p : tf.points()) {
        s.opacity.push_back({p.value, p.rgba.a});
        s.colours.push_back({p.value, glm::dvec3(p.rgba)});
    }
    s.gradientOpacity = tf.gradientOpacity();
    s.refraction = tf.refraction();
    s.normalise();
    return s;
}

double TransferFunctionSpec::opacityAt(double value) const { return interpolate(opacity, value, &OpacityPoint::alpha); }

glm::dvec3 TransferFunctionSpec::colourAt(double value) const { return interpolate(colours, value, &ColourStop::rgb); }

void TransferFunctionSpec::normalise() {
    if (opacity.empty()) throw Error("the transfer function has no opacity points");
    if (colours.empty()) throw Error("the transfer function has no colour stops");
    for (const auto& p : opacity)
        if (!std::isfinite(p.value) || !(p.alpha >= 0.0 && p.alpha <= 1.0))
            throw Error("an opacity point is invalid (value " + std::to_string(p.value) + ", opacity " +
                        std::to_string(p.alpha) + "; opacity must be between 0 and 1)");
    for (const auto& c : colours)
        if (!std::isfinite(c.value) || !(glm::all(glm::greaterThanEqual(c.rgb, glm::dvec3(0.0))) &&
                                         glm::all(glm::lessThanEqual(c.rgb, glm::dvec3(1.0)))))
            throw Error("a colour stop is invalid (value " + std::to_string(c.value) +
                        "; colour components must be between 0 and 1)");
    std::stable_sort(opacity.begin(), opacity.end(), [](auto& a, auto& b) { return a.value < b.value; });
    std::stable_sort(colours.begin(), colours.end(), [](auto& a, auto& b) { return a.value < b.value; });
}

TransferFunction TransferFunctionSpec::build(double valueMin, double valueMax, double referenceLength) const {
    TransferFunctionSpec s = *this;
    s.normalise();
    std::set<double> at;
    for (const auto& p : s.opacity) at.insert(p.value);
    for (const auto& c : s.colours) at.insert(c.value);
    std::vector<TransferFunction::Point> pts;
    for (double v : at) pts.push_back({v, glm::dvec4(s.colourAt(v), s.opacityAt(v))});
    TransferFunction tf(std::move(pts), valueMin, valueMax, referenceLength);
    tf.setGradientOpacity(s.gradientOpacity);
    tf.setRefraction(s.refraction);
    return tf;
}

TransferFunctionSpec TransferFunctionSpec::windowed(double centre, double shift, double scale) const {
    if (!(scale > 0.0) || !std::isfinite(shift)) throw Error("window/level needs a positive width scale");
    TransferFunctionSpec s = *this;
    for (auto& p : s.opacity) p.value = centre + shift + (p.value - centre) * scale;
    for (auto& c : s.colours) c.value = centre + shift + (c.value - centre) * scale;
    for (auto& r : s.refraction) r.value = centre + shift + (r.value - centre) * scale;
    for (auto& g : s.gradientOpacity) g.magnitude *= scale;  // values spread by `scale`: so do their gradients
    return s;
}

}  // namespace hvx::core
