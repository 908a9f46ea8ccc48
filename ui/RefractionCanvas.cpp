#include "ui/RefractionCanvas.h"

namespace hvx::ui {

namespace {
std::vector<CurveRowCanvas::Point> toCurve(const std::vector<core::TransferFunction::RefractionPoint>& points) {
    std::vector<CurveRowCanvas::Point> curve;
    for (const auto& r : points) curve.push_back({r.value, r.index});
    return curve;
}
}  // namespace

RefractionCanvas::RefractionCanvas(QWidget* parent) : CurveRowCanvas(parent) {
    setObjectName("refractionIndex");
    setToolTip(tr("Refraction index \u03bd over the values (thesis \u00a73.2.2): in DVR the rays bend by Snell's law "
                  "where \u03bd changes along them; %1 at the bottom, %2 at the top, 1 (dashed) bends nothing.\nClick to "
                  "add a point, drag to move it, right-click to remove it; no point: no refraction")
                   .arg(kMin)
                   .arg(kMax));
    setAxes(0.0, 1.0, kMin, kMax, 1.0);
}

void RefractionCanvas::setVolume(double valueMin, double valueMax, double slope, double intercept,
                                 const core::VolumeHistogram& histogram) {
    slope_ = slope;
    intercept_ = intercept;
    setAxes(valueMin, valueMax, kMin, kMax, 1.0);
    const double width = histogram.counts.empty() ? 1.0 : (histogram.valueMax - histogram.valueMin) / double(histogram.counts.size());
    setHistogram(histogram.counts, histogram.valueMin, width);
}

void RefractionCanvas::setPoints(const std::vector<core::TransferFunction::RefractionPoint>& storedUnits) {
    setCurve(toCurve(storedUnits));
}

std::vector<core::TransferFunction::RefractionPoint> RefractionCanvas::points() const {
    std::vector<core::TransferFunction::RefractionPoint> out;
    for (const auto& p : curve()) out.push_back({p.x, p.y});
    return out;
}

void RefractionCanvas::showFixed(const QString& why, const std::vector<core::TransferFunction::RefractionPoint>& storedUnits) {
    setReadOnly(why, toCurve(storedUnits));
}

QString RefractionCanvas::leftLabel() const {
    return tr("refraction \u03bd %1\u2013%2   %3").arg(kMin).arg(kMax).arg(xMin_ * slope_ + intercept_, 0, 'g', 4);
}

QString RefractionCanvas::rightLabel() const { return QString::number(xMax_ * slope_ + intercept_, 'g', 4); }

}  // namespace hvx::ui
