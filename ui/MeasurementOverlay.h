#pragma once
#include <QColor>
#include <QPointF>
#include <QRectF>
#include <QSize>
#include <QString>

#include <functional>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "core/reference/MeasurementList.h"

class QPainter;

namespace hvx::ui {

/// Draws measurements over a slice: distances, angles (with the arc at the vertex) and circles,
/// each with its label on a dark box, labels kept inside the view and clear of the ones drawn
/// before. The slice view says where a patient point falls on the screen and whether it lies on
/// the slice.
class MeasurementOverlay {
public:
    /// `toWidget` projects a patient point (LPS mm) on the view; `onSlice` says whether it lies
    /// on the slice shown; `normal` is the plane's, `pixelMm` its pixel size.
    MeasurementOverlay(QPainter& painter, QSize size, std::function<QPointF(const glm::dvec3&)> toWidget,
                       std::function<bool(const glm::dvec3&)> onSlice, const glm::dvec3& normal, double pixelMm);
    /// Every measurement of the list that lies in this slice (all its points), with its label
    /// (M1 70.0 mm …); with a plane point set, a sphere as the circle the slice cuts from it.
    void list(const std::vector<core::Measurement>& items);
    /// A point of the slice's plane (slice views): list() then draws the cut of each sphere.
    void setPlanePoint(const glm::dvec3& p) { planePoint_ = p; }
    /// Whether list() draws `m` on the slice of `normal`: all its points on the slice, and a
    /// region drawn on a slice parallel to it.
    static bool drawnOnSlice(const core::Measurement& m, const std::function<bool(const glm::dvec3&)>& onSlice,
                             const glm::dvec3& normal);
    /// A region drawn on a slice (circle, ellipse, rectangle or outline), closed.
    void region(const core::MeasureRegion& r, const QString& label);
    /// A sphere as seen in the 3D view: its outline, a circle of `radiusPx` about `centre` (widget
    /// positions), with its label.
    void sphere(QPointF centre, double radiusPx, const QString& label);
    /// "70.0 mm", or "70.0 mm (spacing assumed)" when the volume's source gave no spacing.
    static QString lengthText(double mm, bool spacingAssumed);
    /// list() marks its distances as measured in an assumed spacing.
    void setSpacingAssumed(bool assumed) { spacingAssumed_ = assumed; }
    /// "M2  mean 25.6 HU": a region's label and mean.
    static QString regionLabel(const core::Measurement& m);
    /// A small square that can be dragged, at a patient point.
    void handle(const glm::dvec3& at);
    void distance(const glm::dvec3& a, const glm::dvec3& b, const QString& label);
    /// An angle at vertex `b` between the arms to `a` and `c`.
    void angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const QString& label);
    void circle(const glm::dvec3& centre, double radiusMm, const QString& label);
    /// An ellipse about `centre`, semi-axis `a` mm along the unit `axis` and `b` mm along `across`.
    void ellipse(const glm::dvec3& centre, const glm::dvec3& axis, const glm::dvec3& across, double a, double b,
                 const QString& label);
    /// A polygon through `corners` (closed, or an open polyline while it is drawn).
    void outline(const std::vector<glm::dvec3>& corners, bool closed, const QString& label);
    /// A label whose box starts at `topLeft`, moved inside the view and below labels it would cover.
    void label(QPointF topLeft, const QString& text);
    /// Text on a dark box in `area` (wrapped), for the statistics of the circle being drawn.
    void box(const QRectF& area, const QString& text);
    static const QColor kColour;

private:
    bool spacingAssumed_ = false;
    QPainter& p_;
    QSize size_;
    std::function<QPointF(const glm::dvec3&)> toWidget_;
    std::function<bool(const glm::dvec3&)> onSlice_;
    glm::dvec3 normal_;
    double pixelMm_;
    std::vector<QRectF> labels_;
    std::optional<glm::dvec3> planePoint_;  // drawn so far, so that labels do not cover each other
};

}  // namespace hvx::ui
