#include "ui/SliceCrosshair.h"

#include <QPainter>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace hvx::ui {

SliceCrosshair::SliceCrosshair(const core::SlicePlane& plane, QPointF cursor, QSize size, const glm::dvec3& first,
                               const glm::dvec3& second)
    : cursor_(cursor), size_(size) {
    for (const auto& n : {first, second})
        if (const auto d = direction(plane, n)) directions_.push_back(*d);
    if (directions_.size() == 2) {
        const double r = 0.35 * std::min(size.width(), size.height());
        for (const QPointF& d : directions_) {
            handles_.push_back(cursor + r * d);
            handles_.push_back(cursor - r * d);
        }
    } else {
        directions_ = {QPointF(1, 0), QPointF(0, 1)};
    }
}

std::optional<QPointF> SliceCrosshair::direction(const core::SlicePlane& plane, const glm::dvec3& other) {
    if (glm::length(other) == 0.0) return std::nullopt;
    const glm::dvec3 d = glm::cross(plane.normal(), other);
    const QPointF s(glm::dot(d, plane.right), glm::dot(d, plane.down));
    const double l = std::hypot(s.x(), s.y());
    if (l < 1e-9) return std::nullopt;
    return s / l;
}

std::optional<QPointF> SliceCrosshair::handleAt(QPointF pos) const {
    for (const QPointF& h : handles_)
        if (std::hypot(h.x() - pos.x(), h.y() - pos.y()) <= 7.0) return h;
    return std::nullopt;
}

void SliceCrosshair::paint(QPainter& p) const {
    p.setPen(QPen(QColor(80, 200, 255, 180), 1));
    const double reach = std::hypot(size_.width(), size_.height());
    for (const QPointF& d : directions_) {  // a gap of 6 px around the cursor
        p.drawLine(cursor_ + 6 * d, cursor_ + reach * d);
        p.drawLine(cursor_ - 6 * d, cursor_ - reach * d);
    }
    p.setRenderHint(QPainter::Antialiasing);
    p.setBrush(QColor(80, 200, 255, 120));
    for (const QPointF& h : handles_) p.drawEllipse(h, 4.0, 4.0);
    p.setBrush(Qt::NoBrush);
    p.setRenderHint(QPainter::Antialiasing, false);
}

}  // namespace hvx::ui
