#include "ui/TransferFunctionCanvas.h"

#include <QColorDialog>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>

namespace hvx::ui {

namespace {
constexpr double kHandle = 6.0;  // handle radius, pixels
QColor toColor(const glm::dvec3& c) { return QColor::fromRgbF(float(c.r), float(c.g), float(c.b)); }
}  // namespace

TransferFunctionCanvas::TransferFunctionCanvas(QWidget* parent) : QWidget(parent) {
    setMinimumSize(260, 150);
    setFocusPolicy(Qt::ClickFocus);
    setMouseTracking(false);
    setToolTip(tr("Opacity: drag points, click to add, right-click or Delete to remove\n"
                  "Colour bar: click to add a stop, double-click to pick its colour, right-click to remove\n"
                  "Window/level: Ctrl+drag or middle drag (left/right shifts, up/down widens)"));
    spec_.opacity = {{0, 0}, {1, 1}};
    spec_.colours = {{0, {0, 0, 0}}, {1, {1, 1, 1}}};
}

void TransferFunctionCanvas::setRange(double valueMin, double valueMax, double slope, double intercept) {
    min_ = valueMin;
    max_ = valueMax > valueMin ? valueMax : valueMin + 1.0;
    slope_ = slope;
    intercept_ = intercept;
    pinEnds();
    update();
}

void TransferFunctionCanvas::setHistogram(const core::VolumeHistogram& h) {
    histogram_ = h;
    update();
}

void TransferFunctionCanvas::setSpec(const core::TransferFunctionSpec& s) {
    spec_ = s;
    spec_.normalise();
    pinEnds();
    update();
}

void TransferFunctionCanvas::pinEnds() {
    // The curve spans exactly the value range: points outside go, the ends take the curve's values.
    const double a0 = spec_.opacityAt(min_), a1 = spec_.opacityAt(max_);
    std::erase_if(spec_.opacity, [&](const auto& p) { return p.value <= min_ || p.value >= max_; });
    spec_.opacity.insert(spec_.opacity.begin(), {min_, a0});
    spec_.opacity.push_back({max_, a1});
}

QRectF TransferFunctionCanvas::curveRect() const { return QRectF(8, 8, width() - 16, height() - 16 - 26); }
QRectF TransferFunctionCanvas::colourRect() const { return QRectF(8, height() - 8 - 20, width() - 16, 20); }

QPointF TransferFunctionCanvas::opacityPoint(double value, double alpha) const {
    const QRectF r = curveRect();
    return {r.left() + (value - min_) / (max_ - min_) * r.width(), r.bottom() - alpha * r.height()};
}

double TransferFunctionCanvas::valueAt(double x) const {
    const QRectF r = curveRect();
    return min_ + std::clamp((x - r.left()) / r.width(), 0.0, 1.0) * (max_ - min_);
}

int TransferFunctionCanvas::opacityHit(const QPointF& p) const {
    for (int i = 0; i < int(spec_.opacity.size()); ++i) {
        const auto& o = spec_.opacity[std::size_t(i)];
        if (QLineF(opacityPoint(o.value, o.alpha), p).length() <= kHandle + 2) return i;
    }
    return -1;
}

int TransferFunctionCanvas::colourHit(const QPointF& p) const {
    if (!colourRect().adjusted(0, -4, 0, 4).contains(p)) return -1;
    for (int i = 0; i < int(spec_.colours.size()); ++i)
        if (std::abs(opacityPoint(spec_.colours[std::size_t(i)].value, 0).x() - p.x()) <= kHandle) return i;
    return -1;
}

void TransferFunctionCanvas::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    p.fillRect(rect(), palette().base());
    const QRectF r = curveRect();
    p.fillRect(r, QColor(30, 30, 34));
    // Log-scaled histogram.
    if (!histogram_.counts.empty()) {
        double top = 0;
        for (auto c : histogram_.counts) top = std::max(top, std::log1p(double(c)));
        const double bw = r.width() / double(histogram_.counts.size());
        // Bins are over the histogram's own range; map them onto the canvas range.
        for (std::size_t i = 0; i < histogram_.counts.size(); ++i) {
            const double v0 = histogram_.valueMin + (histogram_.valueMax - histogram_.valueMin) * double(i) / double(histogram_.counts.size());
            const double x = opacityPoint(v0, 0).x();
            const double hgt = top > 0 ? std::log1p(double(histogram_.counts[i])) / top * r.height() : 0;
            p.fillRect(QRectF(x, r.bottom() - hgt, std::max(1.0, bw), hgt), QColor(90, 90, 100));
        }
    }
    // Opacity curve, filled with the colours it maps to.
    QPainterPath curve;
    for (std::size_t i = 0; i < spec_.opacity.size(); ++i) {
        const QPointF q = opacityPoint(spec_.opacity[i].value, spec_.opacity[i].alpha);
        i == 0 ? curve.moveTo(q) : curve.lineTo(q);
    }
    QPainterPath fill = curve;
    fill.lineTo(r.bottomRight());
    fill.lineTo(r.bottomLeft());
    fill.closeSubpath();
    QLinearGradient grad(r.topLeft(), r.topRight());
    for (const auto& c : spec_.colours) {
        const double t = (c.value - min_) / (max_ - min_);
        if (t >= 0 && t <= 1) grad.setColorAt(t, toColor(c.rgb));
    }
    grad.setColorAt(0, toColor(spec_.colourAt(min_)));
    grad.setColorAt(1, toColor(spec_.colourAt(max_)));
    p.setOpacity(0.45);
    p.fillPath(fill, grad);
    p.setOpacity(1.0);
    p.setPen(QPen(QColor(240, 240, 240), 1.5));
    p.drawPath(curve);
    for (std::size_t i = 0; i < spec_.opacity.size(); ++i) {
        const QPointF q = opacityPoint(spec_.opacity[i].value, spec_.opacity[i].alpha);
        p.setBrush(int(i) == index_ && drag_ == Drag::Opacity ? QColor(255, 200, 60) : QColor(250, 250, 250));
        p.drawEllipse(q, kHandle - 1, kHandle - 1);
    }
    // Colour bar and its stops.
    const QRectF cr = colourRect();
    QLinearGradient bar(cr.topLeft(), cr.topRight());
    for (int i = 0; i <= 64; ++i) bar.setColorAt(i / 64.0, toColor(spec_.colourAt(min_ + (max_ - min_) * i / 64.0)));
    p.fillRect(cr, bar);
    p.setPen(QColor(200, 200, 200));
    for (const auto& c : spec_.colours) {
        const double x = opacityPoint(c.value, 0).x();
        if (x < cr.left() - 1 || x > cr.right() + 1) continue;
        QPolygonF tri({QPointF(x, cr.top()), QPointF(x - 5, cr.top() - 7), QPointF(x + 5, cr.top() - 7)});
        p.setBrush(toColor(c.rgb));
        p.drawPolygon(tri);
    }
    // Range in physical units.
    p.setPen(QColor(200, 200, 200));
    p.drawText(r.adjusted(4, 2, -4, -2), Qt::AlignTop | Qt::AlignLeft, QString::number(min_ * slope_ + intercept_, 'g', 5));
    p.drawText(r.adjusted(4, 2, -4, -2), Qt::AlignTop | Qt::AlignRight, QString::number(max_ * slope_ + intercept_, 'g', 5));
}

void TransferFunctionCanvas::mousePressEvent(QMouseEvent* e) {
    const QPointF pos = e->position();
    pressPos_ = pos;
    dragStart_ = spec_;
    if (e->button() == Qt::MiddleButton || (e->button() == Qt::LeftButton && (e->modifiers() & Qt::ControlModifier))) {
        drag_ = Drag::WindowLevel;
        return;
    }
    if (const int c = colourHit(pos); c >= 0) {
        if (e->button() == Qt::RightButton && spec_.colours.size() > 1) {
            spec_.colours.erase(spec_.colours.begin() + c);
            emit edited();
        } else if (e->button() == Qt::LeftButton) {
            drag_ = Drag::Colour;
            index_ = c;
        }
        update();
        return;
    }
    if (colourRect().contains(pos) && e->button() == Qt::LeftButton) {  // a new stop, in the colour already there
        const double v = valueAt(pos.x());
        spec_.colours.push_back({v, spec_.colourAt(v)});
        spec_.normalise();
        emit edited();
        update();
        return;
    }
    const int o = opacityHit(pos);
    if (e->button() == Qt::RightButton) {
        if (o > 0 && o + 1 < int(spec_.opacity.size())) {  // the end points stay
            spec_.opacity.erase(spec_.opacity.begin() + o);
            index_ = -1;
            emit edited();
            update();
        }
        return;
    }
    if (e->button() != Qt::LeftButton || !curveRect().adjusted(-kHandle, -kHandle, kHandle, kHandle).contains(pos)) return;
    if (o >= 0) {
        index_ = o;
    } else {  // a new point under the pointer
        const double v = valueAt(pos.x());
        const double a = std::clamp((curveRect().bottom() - pos.y()) / curveRect().height(), 0.0, 1.0);
        auto it = std::upper_bound(spec_.opacity.begin(), spec_.opacity.end(), v,
                                   [](double x, const auto& p) { return x < p.value; });
        if (it == spec_.opacity.begin() || it == spec_.opacity.end()) return;
        index_ = int(it - spec_.opacity.begin());
        spec_.opacity.insert(it, {v, a});
        emit edited();
    }
    drag_ = Drag::Opacity;
    update();
}

void TransferFunctionCanvas::mouseMoveEvent(QMouseEvent* e) {
    const QPointF pos = e->position();
    if (drag_ == Drag::WindowLevel) {
        const double shift = (pos.x() - pressPos_.x()) / curveRect().width() * (max_ - min_);
        const double scale = std::pow(2.0, (pos.y() - pressPos_.y()) / 100.0);
        double lo = dragStart_.opacity.front().value, hi = dragStart_.opacity.back().value;
        for (const auto& p : dragStart_.opacity)
            if (p.alpha > 0) lo = std::min(lo, p.value), hi = std::max(hi, p.value);
        spec_ = dragStart_.windowed(0.5 * (lo + hi), shift, scale);
        pinEnds();
    } else if (drag_ == Drag::Opacity && index_ >= 0) {
        auto& p = spec_.opacity[std::size_t(index_)];
        p.alpha = std::clamp((curveRect().bottom() - pos.y()) / curveRect().height(), 0.0, 1.0);
        const bool end = index_ == 0 || index_ + 1 == int(spec_.opacity.size());
        if (!end) {  // interior points stay between their neighbours
            const double lo = spec_.opacity[std::size_t(index_ - 1)].value, hi = spec_.opacity[std::size_t(index_ + 1)].value;
            const double eps = (max_ - min_) * 1e-4;
            p.value = std::clamp(valueAt(pos.x()), lo + eps, hi - eps);
        }
    } else if (drag_ == Drag::Colour && index_ >= 0) {
        spec_.colours[std::size_t(index_)].value = valueAt(pos.x());
    } else {
        return;
    }
    emit edited();
    update();
}

void TransferFunctionCanvas::mouseReleaseEvent(QMouseEvent*) {
    if (drag_ == Drag::Colour) spec_.normalise();
    drag_ = Drag::None;
    update();
}

void TransferFunctionCanvas::mouseDoubleClickEvent(QMouseEvent* e) {
    const int c = colourHit(e->position());
    if (c < 0) return;
    const QColor chosen = QColorDialog::getColor(toColor(spec_.colours[std::size_t(c)].rgb), this, tr("Colour stop"));
    if (!chosen.isValid()) return;
    spec_.colours[std::size_t(c)].rgb = {chosen.redF(), chosen.greenF(), chosen.blueF()};
    emit edited();
    update();
}

void TransferFunctionCanvas::keyPressEvent(QKeyEvent* e) {
    if ((e->key() == Qt::Key_Delete || e->key() == Qt::Key_Backspace) && index_ > 0 &&
        index_ + 1 < int(spec_.opacity.size())) {
        spec_.opacity.erase(spec_.opacity.begin() + index_);
        index_ = -1;
        emit edited();
        update();
        return;
    }
    QWidget::keyPressEvent(e);
}

}  // namespace hvx::ui
