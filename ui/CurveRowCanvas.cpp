#include "ui/CurveRowCanvas.h"

#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>

namespace hvx::ui {

CurveRowCanvas::CurveRowCanvas(QWidget* parent) : QWidget(parent) {
    setMinimumHeight(56);
    setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Fixed);
}

void CurveRowCanvas::setAxes(double xMin, double xMax, double yMin, double yMax, double neutral) {
    xMin_ = xMin;
    xMax_ = xMax > xMin ? xMax : xMin + 1.0;
    yMin_ = yMin;
    yMax_ = yMax > yMin ? yMax : yMin + 1.0;
    neutral_ = neutral;
    update();
}

void CurveRowCanvas::setHistogram(std::vector<std::uint64_t> counts, double binOrigin, double binWidth) {
    counts_ = std::move(counts);
    binOrigin_ = binOrigin;
    binWidth_ = binWidth > 0 ? binWidth : 1.0;
    update();
}

void CurveRowCanvas::setCurve(std::vector<Point> points) {
    points_ = std::move(points);
    sortPoints();
    update();
}

void CurveRowCanvas::setReadOnly(const QString& why, std::vector<Point> shown) {
    if (readOnlyWhy_.isEmpty()) editTip_ = toolTip();
    readOnlyWhy_ = why;
    shown_ = std::move(shown);
    dragging_ = -1;
    setToolTip(why.isEmpty() ? editTip_ : why);
    update();
}

QRectF CurveRowCanvas::area() const { return QRectF(rect()).adjusted(6, 4, -6, -14); }

QPointF CurveRowCanvas::position(double x, double y) const {
    const QRectF r = area();
    return {r.left() + r.width() * std::clamp((x - xMin_) / (xMax_ - xMin_), 0.0, 1.0),
            r.bottom() - r.height() * std::clamp((y - yMin_) / (yMax_ - yMin_), 0.0, 1.0)};
}

CurveRowCanvas::Point CurveRowCanvas::at(const QPointF& p) const {
    const QRectF r = area();
    return {xMin_ + std::clamp((p.x() - r.left()) / r.width(), 0.0, 1.0) * (xMax_ - xMin_),
            yMin_ + std::clamp((r.bottom() - p.y()) / r.height(), 0.0, 1.0) * (yMax_ - yMin_)};
}

int CurveRowCanvas::hit(const QPointF& p) const {
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const QPointF q = position(points_[i].x, points_[i].y);
        if (std::hypot(q.x() - p.x(), q.y() - p.y()) <= 6.0) return int(i);
    }
    return -1;
}

void CurveRowCanvas::sortPoints() {
    std::sort(points_.begin(), points_.end(), [](const Point& a, const Point& b) { return a.x < b.x; });
}

void CurveRowCanvas::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    p.fillRect(rect(), palette().base());
    const QRectF r = area();
    p.fillRect(r, QColor(30, 30, 34));
    // The histogram, log-scaled, over the bins the row shows.
    double top = 0;
    for (std::size_t i = 0; i < counts_.size(); ++i) {
        const double x0 = binOrigin_ + double(i) * binWidth_;
        if (x0 + binWidth_ > xMin_ && x0 < xMax_) top = std::max(top, std::log1p(double(counts_[i])));
    }
    for (std::size_t i = 0; i < counts_.size() && top > 0; ++i) {
        const double v0 = binOrigin_ + double(i) * binWidth_;
        if (v0 + binWidth_ <= xMin_ || v0 >= xMax_) continue;
        const double x0 = position(v0, yMin_).x(), x1 = position(v0 + binWidth_, yMin_).x();
        const double h = std::log1p(double(counts_[i])) / top * r.height();
        p.fillRect(QRectF(x0, r.bottom() - h, std::max(1.0, x1 - x0), h), QColor(80, 90, 110));
    }
    // The curve, constant beyond its ends; none: the neutral value, dashed.
    const auto& drawn = readOnly() ? shown_ : points_;
    const bool none = drawn.empty();
    QPainterPath curve;
    if (none) {
        curve.moveTo(position(xMin_, neutral_));
        curve.lineTo(position(xMax_, neutral_));
    } else {
        curve.moveTo(QPointF(r.left(), position(xMin_, drawn.front().y).y()));
        for (const auto& q : drawn) curve.lineTo(position(q.x, q.y));
        curve.lineTo(QPointF(r.right(), position(xMin_, drawn.back().y).y()));
    }
    const QColor colour = readOnly() ? QColor(150, 170, 200) : QColor(240, 200, 120);
    p.setPen(QPen(none ? QColor(140, 140, 140) : colour, 1.5, none || readOnly() ? Qt::DashLine : Qt::SolidLine));
    p.drawPath(curve);
    if (!readOnly()) {
        p.setPen(QPen(Qt::black, 1));
        p.setBrush(colour);
        for (const auto& q : drawn) p.drawEllipse(position(q.x, q.y), 4, 4);
    }
    p.setPen(palette().text().color());
    QFont f = font();
    f.setPointSizeF(f.pointSizeF() * 0.8);
    p.setFont(f);
    p.drawText(QRectF(r.left(), r.bottom() + 1, r.width(), 13), Qt::AlignLeft, leftLabel());
    p.drawText(QRectF(r.left(), r.bottom() + 1, r.width(), 13), Qt::AlignRight, rightLabel());
}

void CurveRowCanvas::mousePressEvent(QMouseEvent* e) {
    if (readOnly()) return;
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

void CurveRowCanvas::mouseMoveEvent(QMouseEvent* e) {
    if (readOnly() || dragging_ < 0 || dragging_ >= int(points_.size())) return;
    const auto moved = at(e->position());
    points_[std::size_t(dragging_)] = moved;
    sortPoints();
    for (std::size_t k = 0; k < points_.size(); ++k)  // the dragged point after sorting
        if (points_[k].x == moved.x && points_[k].y == moved.y) dragging_ = int(k);
    update();
    emit edited();
}

void CurveRowCanvas::mouseReleaseEvent(QMouseEvent*) { dragging_ = -1; }

}  // namespace hvx::ui
