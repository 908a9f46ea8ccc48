#include "ui/GradientOpacityCanvas.h"

#include <cmath>

namespace hvx::ui {

GradientOpacityCanvas::GradientOpacityCanvas(QWidget* parent) : CurveRowCanvas(parent) {
    setObjectName("gradientOpacity");
    setToolTip(tr("Gradient opacity: opacity scaled by a curve over the gradient magnitude (per mm), so that "
                  "homogeneous tissue fades and boundaries stay.\nClick to add a point, drag to move it, "
                  "right-click to remove it; no point: no gradient opacity"));
    setAxes(0.0, 100.0, 0.0, 1.0, 1.0);
}

void GradientOpacityCanvas::setVolume(double slope, const core::VolumeHistogram& histogram) {
    slope_ = std::abs(slope) > 0 ? std::abs(slope) : 1.0;
    // Across: up to the 99.5th percentile of the volume's gradients (the steep tail is rare).
    const double top = histogram.gradientPercentile(0.995);
    setAxes(0.0, top > 0 ? top : 100.0 / slope_, 0.0, 1.0, 1.0);
    setHistogram(histogram.gradientCounts, 0.0, histogram.gradientBinWidth);
}

void GradientOpacityCanvas::setPoints(const std::vector<core::TransferFunction::GradientPoint>& storedUnits) {
    std::vector<Point> curve;
    for (const auto& g : storedUnits) curve.push_back({g.magnitude, g.scale});
    setCurve(std::move(curve));
}

std::vector<core::TransferFunction::GradientPoint> GradientOpacityCanvas::points() const {
    std::vector<core::TransferFunction::GradientPoint> out;
    for (const auto& p : curve()) out.push_back({p.x, p.y});
    return out;
}

QString GradientOpacityCanvas::leftLabel() const { return tr("gradient 0"); }

QString GradientOpacityCanvas::rightLabel() const { return tr("%1 per mm").arg(magnitudeMax() * slope_, 0, 'g', 3); }

}  // namespace hvx::ui
