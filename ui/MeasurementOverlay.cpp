#include "ui/MeasurementOverlay.h"

#include <QObject>
#include <QPainter>
#include <QPolygonF>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace hvx::ui {

const QColor MeasurementOverlay::kColour(120, 255, 140);

MeasurementOverlay::MeasurementOverlay(QPainter& painter, QSize size, std::function<QPointF(const glm::dvec3&)> toWidget,
                                       std::function<bool(const glm::dvec3&)> onSlice, const glm::dvec3& normal,
                                       double pixelMm)
    : p_(painter), size_(size), toWidget_(std::move(toWidget)), onSlice_(std::move(onSlice)), normal_(normal),
      pixelMm_(pixelMm) {
    p_.setRenderHint(QPainter::Antialiasing);
}

QString MeasurementOverlay::regionLabel(const core::Measurement& m) {
    QString text = QString::fromStdString(m.label);
    if (m.stats) {
        const QString u = m.stats->units.empty() ? QString() : QStringLiteral(" ") + QString::fromStdString(m.stats->units);
        text += QObject::tr("  mean %1%2").arg(m.stats->mean, 0, 'f', 1).arg(u);
    }
    return text;
}

bool MeasurementOverlay::drawnOnSlice(const core::Measurement& m, const std::function<bool(const glm::dvec3&)>& onSlice,
                                      const glm::dvec3& normal) {
    // Only what lies in this slice: a distance or an angle with a point off it would be drawn
    // shorter or at another angle than it is.
    if (m.kind == core::Measurement::Kind::Distance) return onSlice(m.a) && onSlice(m.b);
    if (m.kind == core::Measurement::Kind::Angle) return onSlice(m.a) && onSlice(m.b) && onSlice(m.c);
    if (!m.region || m.region->kind == core::MeasureRegion::Kind::Sphere || m.region->kind == core::MeasureRegion::Kind::Box)
        return false;
    return onSlice(m.region->centre) && std::abs(std::abs(glm::dot(m.region->normal, normal)) - 1.0) < 1e-6;
}

QString MeasurementOverlay::lengthText(double mm, bool spacingAssumed) {
    return spacingAssumed ? QObject::tr("%1 mm (spacing assumed)").arg(mm, 0, 'f', 1) : QObject::tr("%1 mm").arg(mm, 0, 'f', 1);
}

void MeasurementOverlay::list(const std::vector<core::Measurement>& items) {
    for (const auto& m : items) {
        if (planePoint_ && m.region && m.region->kind == core::MeasureRegion::Kind::Sphere) {
            // The circle this slice cuts from the sphere (none when the slice misses it).
            const auto& r = *m.region;
            const double d = glm::dot(r.centre - *planePoint_, normal_);
            if (std::abs(d) < r.radius) circle(r.centre - d * normal_, std::sqrt(r.radius * r.radius - d * d), regionLabel(m));
            continue;
        }
        if (!drawnOnSlice(m, onSlice_, normal_)) continue;
        const QString name = QString::fromStdString(m.label);
        if (m.kind == core::Measurement::Kind::Distance)
            distance(m.a, m.b, QObject::tr("%1  %2").arg(name, lengthText(m.lengthMm(), spacingAssumed_)));
        else if (m.kind == core::Measurement::Kind::Angle)
            angle(m.a, m.b, m.c, QObject::tr("%1  %2\u00b0").arg(name).arg(m.angleDegrees(), 0, 'f', 1));
        else
            region(*m.region, regionLabel(m));
    }
}

void MeasurementOverlay::region(const core::MeasureRegion& r, const QString& text) {
    if (r.kind == core::MeasureRegion::Kind::Disc) circle(r.centre, r.radius, text);
    else if (r.kind == core::MeasureRegion::Kind::Ellipse) ellipse(r.centre, r.axis, glm::cross(r.normal, r.axis), r.radius, r.radius2, text);
    else if (r.outlined()) outline(r.outline, true, text);
}

void MeasurementOverlay::handle(const glm::dvec3& at) {
    const QPointF c = toWidget_(at);
    p_.setPen(QPen(kColour, 1.0));
    p_.setBrush(QColor(0, 0, 0, 160));
    p_.drawRect(QRectF(c.x() - 3, c.y() - 3, 6, 6));
    p_.setBrush(Qt::NoBrush);
}

void MeasurementOverlay::ellipse(const glm::dvec3& centre, const glm::dvec3& axis, const glm::dvec3& across, double a,
                                 double b, const QString& text) {
    std::vector<glm::dvec3> rim;
    for (int i = 0; i < 96; ++i) {
        const double t = 2 * M_PI * i / 96.0;
        rim.push_back(centre + a * std::cos(t) * axis + b * std::sin(t) * across);
    }
    outline(rim, true, text);
}

void MeasurementOverlay::distance(const glm::dvec3& a3, const glm::dvec3& b3, const QString& text) {
    const QPointF a = toWidget_(a3), b = toWidget_(b3);
    p_.setPen(QPen(kColour, 1.5));
    p_.setBrush(Qt::NoBrush);
    p_.drawLine(a, b);
    p_.drawEllipse(a, 2.5, 2.5);
    p_.drawEllipse(b, 2.5, 2.5);
    const QPointF mid = (a + b) / 2.0;
    if (!text.isEmpty()) label(QPointF(mid.x() + 6, mid.y() - 20), text);
}

void MeasurementOverlay::angle(const glm::dvec3& a3, const glm::dvec3& b3, const glm::dvec3& c3, const QString& text) {
    const QPointF a = toWidget_(a3), b = toWidget_(b3), c = toWidget_(c3);
    p_.setPen(QPen(kColour, 1.5));
    p_.setBrush(Qt::NoBrush);
    p_.drawLine(a, b);
    p_.drawLine(b, c);
    for (const QPointF& q : {a, b, c}) p_.drawEllipse(q, 2.5, 2.5);
    // The arc between the arms, at the vertex (screen angles: y grows downwards).
    const QPointF u = a - b, v = c - b;
    const double lu = std::hypot(u.x(), u.y()), lv = std::hypot(v.x(), v.y());
    if (lu > 1 && lv > 1) {
        const double r = std::min({20.0, lu / 2, lv / 2});
        const double start = std::atan2(-u.y(), u.x());
        const double span = std::remainder(std::atan2(-v.y(), v.x()) - start, 2 * M_PI);
        p_.drawArc(QRectF(b.x() - r, b.y() - r, 2 * r, 2 * r), int(std::lround(glm::degrees(start) * 16)),
                   int(std::lround(glm::degrees(span) * 16)));
    }
    if (!text.isEmpty()) label(QPointF(b.x() + 8, b.y() + 4), text);
}

void MeasurementOverlay::sphere(QPointF c, double r, const QString& text) {
    p_.setPen(QPen(kColour, 1.5, Qt::DashLine));
    p_.setBrush(Qt::NoBrush);
    p_.drawEllipse(c, r, r);
    p_.drawEllipse(c, 2.5, 2.5);
    if (!text.isEmpty()) label(c + QPointF(r * 0.7071 + 6, -r * 0.7071 - 20), text);
}

void MeasurementOverlay::circle(const glm::dvec3& centre, double radiusMm, const QString& text) {
    const QPointF c = toWidget_(centre);
    const double r = radiusMm / pixelMm_;
    p_.setPen(QPen(kColour, 1.5));
    p_.setBrush(Qt::NoBrush);
    p_.drawEllipse(c, r, r);
    if (!text.isEmpty()) label(c + QPointF(r * 0.7071 + 6, -r * 0.7071 - 20), text);
}

void MeasurementOverlay::outline(const std::vector<glm::dvec3>& corners, bool closed, const QString& text) {
    QPolygonF poly;
    for (const auto& c : corners) poly << toWidget_(c);
    p_.setPen(QPen(kColour, 1.5));
    p_.setBrush(Qt::NoBrush);
    if (closed) p_.drawPolygon(poly);
    else p_.drawPolyline(poly);
    if (text.isEmpty() || poly.isEmpty()) return;
    const QRectF box = poly.boundingRect();
    label(QPointF(box.right() + 6, box.top() - 10), text);
}

void MeasurementOverlay::label(QPointF topLeft, const QString& text) {
    QRectF used = p_.boundingRect(QRectF(topLeft, QSizeF(400, 18)), Qt::AlignLeft | Qt::AlignTop, text);
    const auto inside = [&] {
        const double dx = std::min(0.0, size_.width() - 4.0 - used.right()) + std::max(0.0, 4.0 - used.left());
        const double dy = std::min(0.0, size_.height() - 4.0 - used.bottom()) + std::max(0.0, 4.0 - used.top());
        used.translate(dx, dy);
    };
    inside();
    for (int tries = 0; tries < 8; ++tries) {
        const auto hit = std::find_if(labels_.begin(), labels_.end(),
                                      [&](const QRectF& r) { return r.intersects(used.adjusted(-3, -2, 3, 2)); });
        if (hit == labels_.end()) break;
        used.moveTop(hit->bottom() + 3);
        inside();
    }
    labels_.push_back(used.adjusted(-3, -2, 3, 2));
    p_.fillRect(labels_.back(), QColor(0, 0, 0, 170));
    p_.setPen(kColour);
    p_.drawText(used, Qt::AlignLeft | Qt::AlignTop, text);
}

void MeasurementOverlay::box(const QRectF& area, const QString& text) {
    const int flags = Qt::AlignLeft | Qt::AlignTop | Qt::TextWordWrap;
    const QRectF used = p_.boundingRect(area, flags, text);
    labels_.push_back(used.adjusted(-3, -2, 3, 2));
    p_.fillRect(labels_.back(), QColor(0, 0, 0, 170));
    p_.setPen(kColour);
    p_.drawText(area, flags, text);
}

}  // namespace hvx::ui
