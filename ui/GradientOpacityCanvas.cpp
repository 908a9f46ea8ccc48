#include "ui/GradientOpacityCanvas.h"

#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>

namespace hvx::ui {

GradientOpacityCanvas::GradientOpacityCanvas(QWidget* parent) : QWidget(parent) {
    setObjectName("gradientOpacity");
    setMinimumHeight(56);
    setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Fixed);
    setToolTip(tr("Gradient opacity: opacity scaled by a curve over the gradient magnitude (per mm), so that "
                  "homogeneous tissue fades and boundaries stay.\nClick to add a point, drag to move it, "
                  "right-click to remove it; no point: no gradient opacity"));
}

void GradientOpacityCanvas::setVolume(double slope, const core::VolumeHistogram& histogram) {
    slope_ = std::abs(slope) > 0 ? std::abs(slope) : 1.0;
    counts_ = histogram.gradientCounts;
    binWidth_ = histogram.gradientBinWidth;
    // Across: up to the 99.5th percentile of the volume's gradients (the steep tail is rare).
    const double top = histogram.gradientPercentile(0.995);
    magnitudeMax_ = top > 0 ? top : 100.0 / slope_;
    update();
}

void GradientOpacityCanvas::setPoints(std::vector<core::TransferFunction::GradientPoint> storedUnits) {
    points_ = std::move(storedUnits);
    sortPoints();
    update();
}

QRectF GradientOpacityCanvas::area() const { return QRectF(rect()).adjusted(6, 4, -6, -14); }

QPointF GradientOpacityCanvas::position(double magnitude, double scale) const {
    const QRectF r = area();
    return {r.left() + r.width() * std::clamp(magnitude / magnitudeMax_, 0.0, 1.0), r.bottom() - r.height() * scale};
}

core::TransferFunction::GradientPoint GradientOpacityCanvas::at(const QPointF& p) const {
    const QRectF r = area();
    return {std::clamp((p.x() - r.left()) / r.width(), 0.0, 1.0) * magnitudeMax_,
            std::clamp((r.bottom() - p.y()) / r.height(), 0.0, 1.0)};
}

int GradientOpacityCanvas::hit(const QPointF& p) const {
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const QPointF q = position(points_[i].magnitude, points_[i].scale);
        if (std::hypot(q.x() - p.x(), q.y() - p.y()) <= 6.0) return int(i);
    }
    return -1;
}

void GradientOpacityCanvas::sortPoints() {
    std::sort(points_.begin(), points_.end(), [](const auto& a, const auto& b) { return a.magnitude < b.magnitude; });
}

void GradientOpacityCanvas::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    p.fillRect(rect(), palette().base());
    const QRectF r = area();
    p.fillRect(r, QColor(30, 30, 34));
    // Log histogram of gradient magnitudes.
    double top = 0;
    const std::size_t shown = std::min(counts_.size(), std::size_t(std::ceil(magnitudeMax_ / binWidth_)));
    for (std::size_t i = 0; i < shown; ++i) top = std::max(top, std::log1p(double(counts_[i])));
    for (std::size_t i = 0; i < shown && top > 0; ++i) {
        const double x0 = position(double(i) * binWidth_, 0).x(), x1 = position(double(i + 1) * binWidth_, 0).x();
        const double h = std::log1p(double(counts_[i])) / top * r.height();
        p.fillRect(QRectF(x0, r.bottom() - h, std::max(1.0, x1 - x0), h), QColor(80, 90, 110));
    }
    // The curve (flat at 1 when there is none), constant beyond its ends.
    QPainterPath curve;
    if (points_.empty()) {
        curve.moveTo(position(0, 1));
        curve.lineTo(position(magnitudeMax_, 1));
    } else {
        curve.moveTo(QPointF(r.left(), position(0, points_.front().scale).y()));
        for (const auto& q : points_) curve.lineTo(position(q.magnitude, q.scale));
        curve.lineTo(QPointF(r.right(), position(0, points_.back().scale).y()));
    }
    p.setPen(QPen(points_.empty() ? QColor(140, 140, 140) : QColor(240, 200, 120), 1.5, points_.empty() ? Qt::DashLine : Qt::SolidLine));
    p.drawPath(curve);
    p.setPen(QPen(Qt::black, 1));
    p.setBrush(QColor(240, 200, 120));
    for (const auto& q : points_) p.drawEllipse(position(q.magnitude, q.scale), 4, 4);
    p.setPen(palette().text().color());
    QFont f = font();
    f.setPointSizeF(f.pointSizeF() * 0.8);
    p.setFont(f);
    p.drawText(QRectF(r.left(), r.bottom() + 1, r.width(), 13), Qt::AlignLeft, tr("gradient 0"));
    p.drawText(QRectF(r.left(), r.bottom() + 1, r.width(), 13), Qt::AlignRight,
               tr("%1 per mm").arg(magnitudeMax_ * slope_, 0, 'g', 3));
}

void GradientOpacityCanvas::mousePressEvent(QMouseEvent* e) {
    const int i = hit(e->position());
    if (e->button() == Qt::RightButton) {
        if (i >= 0) {
            points_.erase(points_.begin() + i);
            update();
            emit edited();
        }
        return;
    }
    if (e->button() != Qt::LeftButton) return;
    if (i >= 0) {
        dragging_ = i;
        return;
    }
    points_.push_back(at(e->position()));
    sortPoints();
    dragging_ = hit(e->position());
    update();
    emit edited();
}

void GradientOpacityCanvas::mouseMoveEvent(QMouseEvent* e) {
    if (dragging_ < 0 || dragging_ >= int(points_.size())) return;
    const auto moved = at(e->position());
    points_[std::size_t(dragging_)] = moved;
    sortPoints();
    for (std::size_t k = 0; k < points_.size(); ++k)  // the dragged point after sorting
        if (points_[k].magnitude == moved.magnitude && points_[k].scale == moved.scale) dragging_ = int(k);
    update();
    emit edited();
}

void GradientOpacityCanvas::mouseReleaseEvent(QMouseEvent*) { dragging_ = -1; }

}  // namespace hvx::ui
