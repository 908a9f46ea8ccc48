#include "ui/SliceMeasuring.h"

#include "ui/MeasurementOverlay.h"
#include "ui/SliceView.h"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace hvx::ui {

namespace {
constexpr double kHandlePx = 6.0;  // how near the mouse must be to take a handle
}

SliceMeasuring::SliceMeasuring(SliceView& view) : view_(view) {}

void SliceMeasuring::reset() {
    cancel();
    items_.clear();
}

void SliceMeasuring::cancel() {
    if (handle_) items_[handle_->item] = dragFrom_;  // a drag cut short puts the measurement back
    handle_.reset();
    gesture_ = Gesture::None;
    ruler_.reset();
    roi_.reset();
    roiStats_.reset();
    roiError_.clear();
    outline_.clear();
    anglePoints_.clear();
    placingAngle_ = false;
    view_.setMouseTracking(false);
}

void SliceMeasuring::setItems(std::vector<core::Measurement> items) {
    items_ = std::move(items);
    handle_.reset();  // the list changed under the drag: its indices no longer hold
    if (gesture_ == Gesture::Handle) gesture_ = Gesture::None;
    view_.update();
}

void SliceMeasuring::startAngle() {
    if (!view_.reader_) return;
    anglePoints_.clear();
    placingAngle_ = true;
    view_.setMouseTracking(true);  // the arm being placed follows the mouse
    view_.update();
}

std::optional<double> SliceMeasuring::rulerMm() const {
    if (!ruler_) return std::nullopt;
    return glm::length(ruler_->second - ruler_->first);
}

bool SliceMeasuring::key(QKeyEvent* e) {
    if (e->key() == Qt::Key_Escape || e->key() == Qt::Key_Delete) {
        if (e->key() == Qt::Key_Delete && !placingAngle_ && gesture_ == Gesture::None) {
            // The newest measurement of the list drawn on this slice.
            for (auto it = items_.rbegin(); it != items_.rend(); ++it)
                if (view_.onThisSlice(it->region ? it->region->centre : it->a)) {
                    emit view_.removeRequested(it->label);
                    break;
                }
        }
        cancel();
        view_.update();
        return true;
    }
    if (e->key() == Qt::Key_A && !(e->modifiers() & Qt::ControlModifier)) {
        startAngle();
        return true;
    }
    return false;
}

bool SliceMeasuring::press(QMouseEvent* e) {
    gesture_ = Gesture::None;
    if (e->button() != Qt::LeftButton || !view_.reader_) return false;
    const glm::dvec3 at = view_.patientAt(e->position());
    if (placingAngle_) {
        if (anglePoints_.empty()) anglePoints_.push_back(at);
        anglePoints_.back() = at;    // the point that followed the mouse is placed here
        anglePoints_.push_back(at);  // and the next one follows the mouse
        if (anglePoints_.size() == 4) {
            core::Measurement m;
            m.kind = core::Measurement::Kind::Angle;
            m.view = view_.viewName();
            m.a = anglePoints_[0];
            m.b = anglePoints_[1];
            m.c = anglePoints_[2];
            anglePoints_.clear();
            placingAngle_ = false;
            view_.setMouseTracking(false);
            if (glm::length(m.a - m.b) > 0.0 && glm::length(m.c - m.b) > 0.0) emit view_.measured(m);  // an arm of no length: nothing
        }
        view_.update();
        return true;
    }
    const auto mods = e->modifiers() & (Qt::ShiftModifier | Qt::ControlModifier);
    if (mods == Qt::NoModifier) {
        handle_ = handleAt(e->position());
        if (!handle_) return false;
        gesture_ = Gesture::Handle;
        dragFrom_ = items_[handle_->item];
        items_[handle_->item].stats.reset();  // measured again on release
        roi_.reset();
        roiError_.clear();
        return true;
    }
    roi_.reset();
    roiStats_.reset();
    roiError_.clear();
    dragStart_ = at;
    if (mods == (Qt::ShiftModifier | Qt::ControlModifier) || (mods == Qt::ControlModifier && shape_ == RegionShape::Freehand)) {
        gesture_ = Gesture::Outline;
        outline_ = {at};
    } else if (mods == Qt::ShiftModifier) {
        gesture_ = Gesture::Ruler;
        ruler_ = std::make_pair(at, at);
    } else {
        gesture_ = Gesture::Region;
        roi_ = regionTo(at);
    }
    view_.update();
    return true;
}

bool SliceMeasuring::move(QMouseEvent* e) {
    const glm::dvec3 at = view_.patientAt(e->position());
    if (placingAngle_) {
        if (!anglePoints_.empty()) anglePoints_.back() = at;
    } else if (gesture_ == Gesture::Ruler && ruler_) {
        ruler_->second = at;
    } else if (gesture_ == Gesture::Region) {
        roi_ = regionTo(at);
    } else if (gesture_ == Gesture::Outline) {  // a corner every 3 px the mouse moves
        const QPointF last = view_.widgetAt(outline_.back());
        if (std::hypot(e->position().x() - last.x(), e->position().y() - last.y()) >= 3.0) outline_.push_back(at);
    } else if (gesture_ == Gesture::Handle && handle_) {
        drag(*handle_, at);
    } else {
        return false;
    }
    view_.update();
    return true;
}

bool SliceMeasuring::release(QMouseEvent* e) {
    const Gesture gesture = gesture_;
    gesture_ = Gesture::None;
    const glm::dvec3 at = view_.patientAt(e->position());
    if (gesture == Gesture::Outline) {  // the outline closes from its last corner to its first
        outline_.push_back(at);
        roi_ = core::MeasureRegion::polygon(outline_, view_.plane().normal(), 1.0);
        outline_.clear();
    } else if (gesture == Gesture::Region) {
        roi_ = regionTo(at);
    } else if (gesture == Gesture::Ruler && ruler_ && glm::length(ruler_->second - ruler_->first) > 0.0) {
        core::Measurement m;
        m.kind = core::Measurement::Kind::Distance;
        m.view = view_.viewName();
        m.a = ruler_->first;
        m.b = ruler_->second;
        emit view_.measured(m);
    } else if (gesture == Gesture::Handle && handle_) {
        drag(*handle_, at);
        finishHandle();
    }
    if ((gesture == Gesture::Outline || gesture == Gesture::Region) && roi_) {
        roiStats_ = measure(*roi_);
        if (roiStats_) {  // a region with its statistics goes to the measurement list
            core::Measurement m;
            m.kind = core::Measurement::Kind::Region;
            m.view = view_.viewName();
            m.region = *roi_;
            m.stats = *roiStats_;
            emit view_.measured(m);
        }
    }
    view_.update();
    return gesture != Gesture::None;
}

void SliceMeasuring::finishHandle() {
    core::Measurement m = items_[handle_->item];
    handle_.reset();
    roiError_.clear();
    bool ok = true;
    if (m.region) {
        const auto stats = measure(*m.region);
        ok = stats.has_value();
        m.stats = stats;
    } else if (m.kind == core::Measurement::Kind::Distance) {
        ok = glm::length(m.b - m.a) > 0.0;
    } else if (m.kind == core::Measurement::Kind::Angle) {
        ok = glm::length(m.a - m.b) > 0.0 && glm::length(m.c - m.b) > 0.0;
    }
    if (!ok) {  // refused: the measurement stays as it was, with the reason shown
        if (roiError_.isEmpty()) roiError_ = QObject::tr("%1 not changed: an arm of no length").arg(QString::fromStdString(m.label));
        for (auto& item : items_)
            if (item.label == dragFrom_.label) item = dragFrom_;
        return;
    }
    emit view_.edited(m);
}

core::MeasureRegion SliceMeasuring::regionTo(const glm::dvec3& to) const {
    const auto pl = view_.plane();
    const glm::dvec3 n = pl.normal();
    const glm::dvec3 d = to - dragStart_;
    switch (shape_) {
    case RegionShape::Ellipse:  // in the box dragged corner to corner, its axes along the view's edges
        return core::MeasureRegion::ellipse((dragStart_ + to) / 2.0, n, pl.right, std::abs(glm::dot(d, pl.right)) / 2.0,
                                            std::abs(glm::dot(d, pl.down)) / 2.0, 1.0);
    case RegionShape::Rectangle: return core::MeasureRegion::rectangle(dragStart_, to, n, pl.right, 1.0);
    default: return core::MeasureRegion::disc(dragStart_, n, glm::length(d), 1.0);
    }
}

std::optional<core::RegionStatistics> SliceMeasuring::measure(core::MeasureRegion& r) {
    roiError_.clear();
    const auto* reader = view_.reader_.get();
    if (!reader) return std::nullopt;
    // One slice thick: the voxel spacing along the plane's normal.
    const auto& g = reader->geometry();
    double thickness = 0;
    for (int a = 0; a < 3; ++a) thickness += std::abs(glm::dot(r.normal, g.direction[a])) * g.spacing[a];
    r.thickness = thickness;
    // A plane along a voxel layer measures the layer it names ("slice 25/48"): between two
    // layers it would take half of each, or both.
    const int axis = view_.nearestAxis();
    if (std::abs(std::abs(glm::dot(r.normal, g.direction[axis])) - 1.0) < 1e-9) {
        const glm::dvec3 index(glm::inverse(g.indexToPatient()) * glm::dvec4(r.centre, 1.0));
        r = r.movedBy((double(std::lround(index[axis])) - index[axis]) * g.spacing[axis] * g.direction[axis]);
    }
    try {
        return core::RegionStatistics::compute(*reader, r);
    } catch (const std::exception& ex) {
        roiError_ = QString::fromStdString(ex.what());
        return std::nullopt;
    }
}

std::vector<glm::dvec3> SliceMeasuring::handlePoints(const core::Measurement& m) const {
    const auto pl = view_.plane();
    if (!MeasurementOverlay::drawnOnSlice(m, [this](const glm::dvec3& x) { return view_.onThisSlice(x); }, pl.normal()))
        return {};
    if (m.kind == core::Measurement::Kind::Distance) return {m.a, m.b};
    if (m.kind == core::Measurement::Kind::Angle) return {m.a, m.b, m.c};
    if (!m.region) return {};
    const auto& r = *m.region;
    std::vector<glm::dvec3> points{r.centre};
    if (r.kind == core::MeasureRegion::Kind::Disc) points.push_back(r.centre + r.radius * pl.right);
    if (r.kind == core::MeasureRegion::Kind::Ellipse) {
        points.push_back(r.centre + r.radius * r.axis);
        points.push_back(r.centre + r.radius2 * glm::cross(r.normal, r.axis));
    }
    if (r.kind == core::MeasureRegion::Kind::Rectangle) points.insert(points.end(), r.outline.begin(), r.outline.end());
    return points;
}

std::vector<QPointF> SliceMeasuring::handles() const {
    std::vector<QPointF> out;
    if (!view_.reader_) return out;
    for (const auto& m : items_)
        for (const auto& p : handlePoints(m)) out.push_back(view_.widgetAt(p));
    return out;
}

double SliceMeasuring::nearestHandlePx(QPointF pos) const {
    double best = std::numeric_limits<double>::infinity();
    for (const QPointF& h : handles()) best = std::min(best, std::hypot(h.x() - pos.x(), h.y() - pos.y()));
    return best;
}

std::optional<SliceMeasuring::Handle> SliceMeasuring::handleAt(QPointF pos) const {
    std::optional<Handle> best;
    double bestPx = kHandlePx;
    // The newest first: it is drawn on top.
    for (std::size_t i = items_.size(); i-- > 0;) {
        const auto points = handlePoints(items_[i]);
        for (std::size_t k = 0; k < points.size(); ++k) {
            const QPointF w = view_.widgetAt(points[k]);
            const double px = std::hypot(w.x() - pos.x(), w.y() - pos.y());
            if (px < bestPx) bestPx = px, best = Handle{i, int(k)};
        }
    }
    return best;
}

void SliceMeasuring::drag(const Handle& h, const glm::dvec3& to) {
    core::Measurement& m = items_[h.item];
    const core::Measurement& from = dragFrom_;
    if (m.kind == core::Measurement::Kind::Distance || m.kind == core::Measurement::Kind::Angle) {
        (h.point == 0 ? m.a : h.point == 1 ? m.b : m.c) = to;
        return;
    }
    if (!m.region) return;
    const auto& r0 = *from.region;
    auto& r = *m.region;
    if (h.point == 0) {  // the centre: the whole region moves, in the plane
        const glm::dvec3 d = to - r0.centre;
        r = r0.movedBy(d - glm::dot(d, r0.normal) * r0.normal);
        return;
    }
    const glm::dvec3 d = to - r0.centre;
    if (r.kind == core::MeasureRegion::Kind::Disc) {
        r.radius = glm::length(d - glm::dot(d, r0.normal) * r0.normal);
    } else if (r.kind == core::MeasureRegion::Kind::Ellipse) {
        (h.point == 1 ? r.radius : r.radius2) =
            std::abs(glm::dot(d, h.point == 1 ? r0.axis : glm::cross(r0.normal, r0.axis)));
    } else if (r.kind == core::MeasureRegion::Kind::Rectangle) {  // the opposite corner stays
        const glm::dvec3 opposite = r0.outline[std::size_t((h.point - 1 + 2) % 4)];
        r = core::MeasureRegion::rectangle(opposite, to, r0.normal, r0.outline[1] - r0.outline[0], r0.thickness);
    }
}

QString SliceMeasuring::statisticsText() const {
    const auto* reader = view_.reader_.get();
    if (!reader) return {};
    if (!(roi_ && roiStats_ && view_.onThisSlice(roi_->centre))) return roiError_;
    const QString unit = reader->geometry().spacingAssumed ? QObject::tr(" (spacing assumed)") : QString();
    const auto& s = *roiStats_;
    const QString u = s.units.empty() ? QString() : QStringLiteral(" ") + QString::fromStdString(s.units);
    QString text = QObject::tr("mean %1%2, SD %3\nmin %4, max %5\n%6 voxels, %7 mm\u00b2%8")
                       .arg(s.mean, 0, 'f', 1).arg(u).arg(s.sd, 0, 'f', 1).arg(s.min, 0, 'g', 6).arg(s.max, 0, 'g', 6)
                       .arg(s.voxels).arg(s.areaMm2, 0, 'f', 1).arg(unit);
    if (!s.note.empty()) text += "\n" + QString::fromStdString(s.note);
    if (view_.slabMm() > 0)  // the statistics are the thin slice's voxels, not the slab's MIP, MinIP or mean
        text += "\n" + QObject::tr("of the one slice at the crosshair, not the %1 mm slab shown").arg(view_.slabMm(), 0, 'f', 1);
    return text;
}

void SliceMeasuring::paint(QPainter& p) {
    const auto* reader = view_.reader_.get();
    if (!reader) return;
    const auto pl = view_.plane();
    MeasurementOverlay overlay(p, view_.size(), [this](const glm::dvec3& x) { return view_.widgetAt(x); },
                               [this](const glm::dvec3& x) { return view_.onThisSlice(x); }, pl.normal(), pl.pixelMm);
    overlay.setPlanePoint(pl.centre);
    overlay.setSpacingAssumed(reader->geometry().spacingAssumed);
    // The statistics of the last region (or why it has none) at the top left, clear of the
    // letters and the window.
    const QString text = statisticsText();
    if (!text.isEmpty()) overlay.box(QRectF(6, 22, std::max(80, view_.width() / 2), view_.height() / 2), text);
    overlay.list(items_);
    for (const auto& m : items_)
        for (const auto& h : handlePoints(m)) overlay.handle(h);
    // What is being drawn now (the list draws it once it is made).
    if (gesture_ == Gesture::Region && roi_) overlay.region(*roi_, {});
    if (outline_.size() >= 2) overlay.outline(outline_, false, {});
    if (ruler_ && gesture_ == Gesture::Ruler && view_.onThisSlice(ruler_->first)) {
        overlay.distance(ruler_->first, ruler_->second,
                         MeasurementOverlay::lengthText(*rulerMm(), reader->geometry().spacingAssumed));
    }
    if (anglePoints_.size() >= 2) {
        core::Measurement m;
        m.kind = core::Measurement::Kind::Angle;
        m.a = anglePoints_[0], m.b = anglePoints_[1], m.c = anglePoints_.size() >= 3 ? anglePoints_[2] : anglePoints_[1];
        overlay.angle(m.a, m.b, m.c,
                      anglePoints_.size() >= 3 ? QObject::tr("%1\u00b0").arg(m.angleDegrees(), 0, 'f', 1) : QString());
    }
}

}  // namespace hvx::ui
