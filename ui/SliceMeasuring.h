#pragma once
#include <QPointF>
#include <QString>

#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "core/reference/MeasurementList.h"
#include "core/reference/RegionStatistics.h"

class QKeyEvent;
class QMouseEvent;
class QPainter;

namespace hvx::ui {

class SliceView;

/// What Ctrl-drag draws on a slice: a circle from its centre, an ellipse or a rectangle corner
/// to corner (its sides along the view's edges), or a freehand outline (also Ctrl+Shift-drag).
enum class RegionShape { Circle, Ellipse, Rectangle, Freehand };

/// The measuring one slice view does with the mouse and keys: Shift-drag a distance, Ctrl-drag a
/// region of the chosen shape (its statistics from the octree's level 0, snapped to the slice
/// shown, one slice thick), Ctrl+Shift-drag a freehand outline, A then three clicks an angle;
/// and the measurements of the list drawn on this slice, each with its handles: dragging a
/// distance's or an angle's point moves it, a region's centre moves the region, its rim (a
/// circle's radius, an ellipse's axis ends, a rectangle's corners) reshapes it, and the region
/// is measured again on release (SliceView::edited). Esc cancels; Del asks to remove the newest
/// measurement on this slice.
///
/// Threading: GUI thread only (its view's).
class SliceMeasuring {
public:
    explicit SliceMeasuring(SliceView& view);
    /// A new volume: nothing in progress, no list.
    void reset();
    /// Mouse and key events the view passes on; true when taken.
    bool press(QMouseEvent* e);
    bool move(QMouseEvent* e);
    bool release(QMouseEvent* e);
    bool key(QKeyEvent* e);
    /// Draws the list's measurements on this slice, their handles, and what is being drawn.
    void paint(QPainter& p);
    /// The next three clicks place an angle's arm end, vertex and other arm end.
    void startAngle();
    void setItems(std::vector<core::Measurement> items);
    void setRegionShape(RegionShape shape) { shape_ = shape; }
    RegionShape regionShape() const { return shape_; }
    std::optional<double> rulerMm() const;
    const std::vector<glm::dvec3>& anglePoints() const { return anglePoints_; }
    /// Whether the next clicks place an angle (A was pressed).
    bool placingAngle() const { return placingAngle_; }
    const std::optional<core::MeasureRegion>& roi() const { return roi_; }
    const std::optional<core::RegionStatistics>& roiStatistics() const { return roiStats_; }
    /// Why the last region could not be measured (empty when it was).
    const QString& roiError() const { return roiError_; }
    /// What the view shows at its top left for the last region: its statistics and what they
    /// are of (a slab shown is not what was measured), or why it has none; empty off its slice.
    QString statisticsText() const;
    /// Widget positions of the handles of the measurements drawn on this slice.
    std::vector<QPointF> handles() const;
    /// How far (px) the nearest of those handles lies from `pos` (infinity when there is none).
    double nearestHandlePx(QPointF pos) const;

private:
    enum class Gesture { None, Ruler, Region, Outline, Handle };
    struct Handle {
        std::size_t item;  ///< index in items_
        int point;         ///< see handlePoints()
    };
    /// A measurement's handles in patient space, when it is drawn on this slice (else none):
    /// a distance's ends; an angle's end, vertex and end; a region's centre first, then a
    /// circle's rim point, an ellipse's two axis ends or a rectangle's corners.
    std::vector<glm::dvec3> handlePoints(const core::Measurement& m) const;
    std::optional<Handle> handleAt(QPointF pos) const;
    /// Moves handle `h` of items_[h.item] (from dragFrom_) to `to`.
    void drag(const Handle& h, const glm::dvec3& to);
    /// The region drawn from dragStart_ to `to` with the chosen shape (not yet measured).
    core::MeasureRegion regionTo(const glm::dvec3& to) const;
    /// Snaps `r` onto the slice shown (one slice thick) and measures it; none, with roiError_
    /// saying why, when it cannot be.
    std::optional<core::RegionStatistics> measure(core::MeasureRegion& r);
    void finishHandle();
    /// Ends whatever is in progress (a drag puts its measurement back) and hides the statistics.
    void cancel();

    SliceView& view_;
    RegionShape shape_ = RegionShape::Circle;
    Gesture gesture_ = Gesture::None;
    glm::dvec3 dragStart_{0.0};
    std::optional<std::pair<glm::dvec3, glm::dvec3>> ruler_;
    std::optional<core::MeasureRegion> roi_;
    std::optional<core::RegionStatistics> roiStats_;
    QString roiError_;
    std::vector<glm::dvec3> outline_;       // the freehand outline being drawn
    std::vector<glm::dvec3> anglePoints_;   // the angle being placed: clicked points, then the mouse's
    bool placingAngle_ = false;
    std::vector<core::Measurement> items_;  // the list's, to draw
    std::optional<Handle> handle_;          // the handle being dragged
    core::Measurement dragFrom_;            // its measurement before the drag
};

}  // namespace hvx::ui
