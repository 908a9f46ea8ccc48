// VolumeView's input: the mouse, the wheel, pinch and keys (rotate, pan, zoom, standard views),
// picking points on the surface for distances and spheres, dragging the tools and the crop box's handles.
#include "ui/VolumeView.h"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QNativeGestureEvent>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "ui/VolumeViewScene.h"

namespace hvx::ui {

void VolumeView::editTools(const core::ToolSet& tools) {
    settings_.tools = tools;
    emit toolsEdited(tools);
    interacted();
}

void VolumeView::interacted() {
    settle_.start();
    update();
}

void VolumeView::mousePressEvent(QMouseEvent* e) {
    lastPos_ = e->position().toPoint();
    if (picking_ != Picking::None && e->button() == Qt::LeftButton) {  // D or B: a point on the surface
        const bool sphere = picking_ == Picking::Sphere;
        const QString what = sphere ? tr("Sphere") : tr("Distance");
        const auto at = surfaceAt(e->position());
        if (!at) {
            emit hint(tr("%1: nothing under the cursor; click on the volume (Esc cancels)").arg(what));
            return;
        }
        picked_.push_back(*at);
        if (picked_.size() == 2) {
            core::Measurement m;
            m.view = "3D";
            m.a = picked_[0];
            m.b = picked_[1];
            picking_ = Picking::None;
            picked_.clear();
            if (sphere) {
                m.kind = core::Measurement::Kind::Region;
                m.region = core::MeasureRegion::sphere(m.a, glm::length(m.b - m.a));
                try {
                    m.stats = core::RegionStatistics::compute(*scene_->reader, *m.region);
                    emit hint(tr("Sphere: radius %1 mm, %2 voxels").arg(m.region->radius, 0, 'f', 1).arg(m.stats->voxels));
                    emit measured(m);
                } catch (const std::exception& ex) {
                    emit hint(tr("Sphere not measured: %1").arg(QString::fromStdString(ex.what())));
                }
            } else {
                m.kind = core::Measurement::Kind::Distance;
                emit hint(tr("Distance: %1 mm").arg(m.lengthMm(), 0, 'f', 1));
                emit measured(m);
            }
        } else {
            emit hint(sphere ? tr("Sphere: click a point of its rim") : tr("Distance: click its other end"));
        }
        update();
        return;
    }
    if (const auto crop = cropHandlesNow(); crop && e->button() == Qt::LeftButton && e->modifiers() == Qt::NoModifier) {
        if ((cropFace_ = crop->faceAt(settings_.crop, e->position()))) {  // a crop box face's handle
            cropPress_ = settings_.crop;
            cropFrom_ = e->position();
            return;
        }
    }
    const bool modified = e->modifiers() & (Qt::ControlModifier | Qt::AltModifier);
    if (e->button() == Qt::LeftButton && modified) {  // tools: pick on release, or drag the probes
        toolDrag_.press(lastPos_);
        return;
    }
    dragging_ = true;
    dragButton_ = e->button();
}

bool VolumeView::project(const glm::dvec3& p, QPointF& out, double& depth) const {
    const auto v = camera_.view(width(), height());
    const glm::dvec3 rel = p - v.eye;
    depth = -glm::dot(rel, camera_.back());
    if (depth <= 1e-6) return false;
    const double t = std::tan(glm::radians(v.fovYDegrees) / 2.0);
    const double nx = glm::dot(rel, camera_.right()) / depth / (t * double(width()) / height());
    const double ny = glm::dot(rel, camera_.up()) / depth / t;
    out = QPointF((nx + 1.0) / 2.0 * width(), (1.0 - ny) / 2.0 * height());
    return true;
}

std::optional<QPointF> VolumeView::projected(const glm::dvec3& p) const {
    QPointF at;
    double depth = 0;
    if (!project(p, at, depth)) return std::nullopt;
    return at;
}

void VolumeView::mouseMoveEvent(QMouseEvent* e) {
    const QPoint pos = e->position().toPoint();
    const QPoint d = pos - lastPos_;
    lastPos_ = pos;
    if (cropFace_) {
        if (const auto crop = cropHandlesNow()) emit cropDragged(crop->dragged(cropPress_, *cropFace_, cropFrom_, e->position()));
        return;
    }
    if (toolDrag_.active()) {  // Ctrl+drag moves the probes or the clip plane (ui/ToolDragger)
        if (auto tools = toolDrag_.move(pos, d, e->modifiers() & Qt::ShiftModifier, settings_.tools, camera_, width(),
                                        height()))
            editTools(*tools);
        return;
    }
    if (!dragging_) return;
    const bool pan = dragButton_ == Qt::MiddleButton || (dragButton_ == Qt::LeftButton && (e->modifiers() & Qt::ShiftModifier));
    if (pan) camera_.pan(d.x(), d.y(), height());
    else if (dragButton_ == Qt::RightButton) camera_.zoom(std::pow(1.005, -d.y()));
    else if (dragButton_ == Qt::LeftButton) camera_.rotate(d.x(), d.y(), height());
    update();
}

void VolumeView::mouseReleaseEvent(QMouseEvent* e) {
    cropFace_.reset();
    if (toolDrag_.release()) {
        if (const auto at = surfaceAt(e->position())) emit surfacePicked(*at, (e->modifiers() & Qt::AltModifier) != 0);
    }
    dragging_ = false;
    update();  // the next frame is full quality
}

std::optional<glm::dvec3> VolumeView::surfaceAt(QPointF pos) const {
    if (!scene_ || lastDepth_.empty()) return std::nullopt;
    const double sx = pos.x() / std::max(1, width()) * lastView_.width;
    const double sy = pos.y() / std::max(1, height()) * lastView_.height;
    const int px = std::clamp(int(sx), 0, lastView_.width - 1), py = std::clamp(int(sy), 0, lastView_.height - 1);
    const float depth = lastDepth_[std::size_t(py) * std::size_t(lastView_.width) + std::size_t(px)];
    if (!std::isfinite(depth)) return std::nullopt;
    glm::dvec3 o, d;
    lastView_.ray(px, py, o, d);
    return o + d * double(depth);
}

void VolumeView::requestGlFormat() {
    QSurfaceFormat format;
    format.setVersion(4, 5);
    format.setProfile(QSurfaceFormat::CoreProfile);
    QSurfaceFormat::setDefaultFormat(format);
}

void VolumeView::startDistance() {
    if (!scene_) return;
    picking_ = Picking::Distance;
    picked_.clear();
    emit hint(tr("Distance: click its first end on the volume (Esc cancels)"));
}

void VolumeView::setCropEditing(bool on) {
    cropEditing_ = on;
    update();
}

std::optional<CropBoxHandles> VolumeView::cropHandlesNow() const {
    if (!cropEditing_ || !scene_) return std::nullopt;
    return CropBoxHandles(
        scene_->space, scene_->reader->geometry().dims,
        [this](const glm::dvec3& x) { return projected(x); },
        [this](QPointF pos) {
            glm::dvec3 o, d;
            camera_.view(width(), height()).ray(pos.x() - 0.5, pos.y() - 0.5, o, d);  // (ray() takes pixel indices)
            return std::make_pair(o, d);
        });
}

std::vector<glm::dvec3> VolumeView::cropHandlePoints() const {
    std::vector<glm::dvec3> out;
    if (const auto crop = cropHandlesNow())
        for (int face = 0; face < 6; ++face) out.push_back(crop->faceCentre(settings_.crop, face));
    return out;
}

std::vector<QPointF> VolumeView::cropHandles() const {
    std::vector<QPointF> out;
    for (const auto& p : cropHandlePoints())
        if (const auto at = projected(p)) out.push_back(*at);
    return out;
}

void VolumeView::startSphere() {
    if (!scene_) return;
    picking_ = Picking::Sphere;
    picked_.clear();
    emit hint(tr("Sphere: click its centre on the volume (Esc cancels)"));
}

void VolumeView::setMeasurements(std::vector<core::Measurement> items) {
    measurements_.clear();
    for (auto& m : items)
        if (m.view == "3D") measurements_.push_back(std::move(m));
    update();
}

void VolumeView::wheelEvent(QWheelEvent* e) {
    const double steps = !e->pixelDelta().isNull() ? e->pixelDelta().y() / 60.0 : e->angleDelta().y() / 120.0;
    if (e->modifiers() & Qt::ControlModifier)  // Ctrl+wheel scales the probes
        if (auto tools = ToolDragger::scaled(settings_.tools, steps)) {
            editTools(*tools);
            return;
        }
    camera_.zoom(std::pow(1.1, steps));
    interacted();
}

bool VolumeView::event(QEvent* e) {
    if (e->type() == QEvent::NativeGesture) {  // touchpad pinch
        auto* g = static_cast<QNativeGestureEvent*>(e);
        if (g->gestureType() == Qt::ZoomNativeGesture) {
            camera_.zoom(1.0 + g->value());
            interacted();
            return true;
        }
    }
    return QOpenGLWidget::event(e);
}

void VolumeView::keyPressEvent(QKeyEvent* e) {
    using S = core::OrbitCamera::Standard;
    switch (e->key()) {
    case Qt::Key_A: camera_.setStandard(S::Anterior); break;
    case Qt::Key_P: camera_.setStandard(S::Posterior); break;
    case Qt::Key_L: camera_.setStandard(S::Left); break;
    case Qt::Key_R: camera_.setStandard(S::Right); break;
    case Qt::Key_S: camera_.setStandard(S::Superior); break;
    case Qt::Key_I: camera_.setStandard(S::Inferior); break;
    case Qt::Key_Home: resetView(); break;
    case Qt::Key_D: startDistance(); return;
    case Qt::Key_B: startSphere(); return;
    case Qt::Key_Escape:
        picking_ = Picking::None;
        picked_.clear();
        update();
        return;
    case Qt::Key_Left: camera_.rotate(-height() / 36.0, 0, height()); break;
    case Qt::Key_Right: camera_.rotate(height() / 36.0, 0, height()); break;
    case Qt::Key_Up: camera_.rotate(0, -height() / 36.0, height()); break;
    case Qt::Key_Down: camera_.rotate(0, height() / 36.0, height()); break;
    case Qt::Key_Plus:
    case Qt::Key_Equal: camera_.zoom(1.1); break;
    case Qt::Key_Minus: camera_.zoom(1.0 / 1.1); break;
    default: QOpenGLWidget::keyPressEvent(e); return;
    }
    interacted();
}

}  // namespace hvx::ui
