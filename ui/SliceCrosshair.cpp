#include "ui/SliceCrosshair.h"

#include <QPainter>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace hvx::ui {

SliceCrosshair::SliceCrosshair(const core::SlicePlane& plane, const glm::dvec3& cursor, const Other& first,
                               const Other& second)
    : size_(plane.width, plane.height) {
    auto widget = [&](const glm::dvec3& x) {
        const glm::dvec2 p = plane.pixelOf(x);
        return QPointF(p.x, p.y);
    };
    const glm::dvec3 n = plane.normal();
    const glm::dvec3 onPlane = cursor - n * glm::dot(n, cursor - plane.centre);  // the cursor on this plane
    for (const Other& o : {first, second}) {
        const auto d = direction(plane, o.normal);
        if (!d) continue;
        // Along this plane, across the line, from the cursor to where the other plane lies.
        const glm::dvec3 across = glm::cross(n, glm::normalize(glm::cross(n, o.normal)));
        const double rate = glm::dot(o.normal, across);
        const double s = std::abs(rate) > 1e-9 ? glm::dot(o.normal, o.point - onPlane) / rate : 0.0;
        directions_.push_back(*d);
        anchors_.push_back(widget(onPlane + s * across));
    }
    centre_ = widget(onPlane);
    if (directions_.size() == 2) {
        // The lines cross where a0 + u·d0 = a1 + v·d1 (they are not parallel: the planes differ).
        const QPointF a = anchors_[1] - anchors_[0], d0 = directions_[0], d1 = directions_[1];
        const double det = d0.x() * -d1.y() + d1.x() * d0.y();
        if (std::abs(det) > 1e-9) centre_ = anchors_[0] + d0 * ((a.x() * -d1.y() + d1.x() * a.y()) / det);
        const double r = 0.35 * std::min(plane.width, plane.height);
        for (const QPointF& d : directions_) {
            handles_.push_back(centre_ + r * d);
            handles_.push_back(centre_ - r * d);
        }
    } else {
        directions_ = {QPointF(1, 0), QPointF(0, 1)};
        anchors_ = {centre_, centre_};
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
    for (const QPointF& d : directions_) {  // through the crossing, with a gap of 6 px around it
        p.drawLine(centre_ + 6 * d, centre_ + reach * d);
        p.drawLine(centre_ - 6 * d, centre_ - reach * d);
    }
    p.setRenderHint(QPainter::Antialiasing);
    p.setBrush(QColor(80, 200, 255, 120));
    for (const QPointF& h : handles_) p.drawEllipse(h, 4.0, 4.0);
    p.setBrush(Qt::NoBrush);
    p.setRenderHint(QPainter::Antialiasing, false);
}

}  // namespace hvx::ui
