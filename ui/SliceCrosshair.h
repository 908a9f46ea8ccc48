#pragma once
#include <QPointF>
#include <QSize>

#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "core/reference/SliceSampler.h"

class QPainter;

namespace hvx::ui {

/// The crosshair of a slice view: the lines where the other two planes cut this one, through
/// the cursor, with a rotation handle on either side of each line (plain horizontal and
/// vertical lines without handles when the other planes are not known).
class SliceCrosshair {
public:
    /// `plane` is the view's, `cursor` the cursor's widget position, `others` the other planes'
    /// normals (zero when not known).
    SliceCrosshair(const core::SlicePlane& plane, QPointF cursor, QSize size, const glm::dvec3& first,
                   const glm::dvec3& second);
    /// Screen direction (unit) of the line where a plane with normal `other` cuts `plane`, or none
    /// when they are parallel or `other` is zero.
    static std::optional<QPointF> direction(const core::SlicePlane& plane, const glm::dvec3& other);
    /// The handles' widget positions (two per line; none without the other planes).
    const std::vector<QPointF>& handles() const { return handles_; }
    /// The handle within 7 px of `pos`, if any.
    std::optional<QPointF> handleAt(QPointF pos) const;
    void paint(QPainter& p) const;

private:
    QPointF cursor_;
    QSize size_;
    std::vector<QPointF> directions_;
    std::vector<QPointF> handles_;
};

}  // namespace hvx::ui
