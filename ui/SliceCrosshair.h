#pragma once
#include <QPointF>
#include <QSize>

#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "core/reference/SliceSampler.h"

class QPainter;

namespace hvx::ui {

/// The crosshair of a slice view: the lines where the other two planes cut this one, each drawn
/// where that plane lies (a native plane sits on the nearest voxel layer, up to half a slice
/// from the cursor), with a rotation handle on either side of each line (plain horizontal and
/// vertical lines through the cursor, without handles, when the other planes are not known).
class SliceCrosshair {
public:
    /// One of the other views' planes: its normal (zero when not known) and a point on it.
    struct Other {
        glm::dvec3 normal{0.0};
        glm::dvec3 point{0.0};
        bool operator==(const Other& o) const { return normal == o.normal && point == o.point; }
    };
    /// `plane` is the view's (its width and height the widget's), `cursor` the cursor's patient
    /// position.
    SliceCrosshair(const core::SlicePlane& plane, const glm::dvec3& cursor, const Other& first, const Other& second);
    /// Screen direction (unit) of the line where a plane with normal `other` cuts `plane`, or none
    /// when they are parallel or `other` is zero.
    static std::optional<QPointF> direction(const core::SlicePlane& plane, const glm::dvec3& other);
    /// The handles' widget positions (two per line; none without the other planes).
    const std::vector<QPointF>& handles() const { return handles_; }
    /// The handle within 7 px of `pos`, if any.
    std::optional<QPointF> handleAt(QPointF pos) const;
    void paint(QPainter& p) const;

    /// Where each line passes nearest the cursor (widget positions, one per line).
    const std::vector<QPointF>& anchors() const { return anchors_; }
    /// Where the lines cross (the cursor where they are not known): the handles turn about it.
    QPointF centre() const { return centre_; }

private:
    QSize size_;
    QPointF centre_;
    std::vector<QPointF> anchors_;
    std::vector<QPointF> directions_;
    std::vector<QPointF> handles_;
};

}  // namespace hvx::ui
