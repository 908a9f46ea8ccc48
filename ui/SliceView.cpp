#include "ui/SliceView.h"

#include "core/reference/SliceComposer.h"
#include "ui/SliceLayers.h"

#include "ui/EdgeLabels.h"
#include "ui/MeasurementOverlay.h"
#include "ui/SliceCrosshair.h"

#include <QMouseEvent>
#include <QKeyEvent>
#include <QPainter>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

namespace hvx::ui {

SliceView::SliceView(core::SlicePlane::Orientation orientation, QWidget* parent)
    : QWidget(parent), orientation_(orientation) {
    setMinimumSize(120, 120);
    setFocusPolicy(Qt::StrongFocus);
    setToolTip(tr("Click or drag: move the cursor \u2022 Wheel, Up/Down: next slice (Page Up/Down: ten) \u2022 "
                  "Right drag: window/level\n] / [: thicker / thinner slab \u2022 M: MIP, MinIP, mean\n"
                  "Shift-drag: distance \u2022 Ctrl-drag: region statistics (its shape in the Measurements dock) \u2022 "
                  "Ctrl+Shift-drag: freehand outline \u2022 A, then three clicks: angle \u2022 drag a handle: edit\n"
                  "Esc: cancel \u2022 Del: remove the newest measurement on this slice\n"
                  "Drag a crosshair handle: turn the other planes \u2022 V: slice along the 3D view \u2022 O: reset\n"
                  "1-9: window presets (the DICOM's, then for CT: brain, subdural, stroke, bone, lung, "
                  "mediastinum, abdomen, liver)"));
}

void SliceView::setLayers(SliceLayers* layers) {
    if (layers_) disconnect(layers_, nullptr, this, nullptr);
    layers_ = layers;
    if (layers_) connect(layers_, &SliceLayers::changed, this, &SliceView::resample);
    resample();
}

void SliceView::showTimePoint(std::shared_ptr<const core::OctreeReader> reader) {
    if (!reader_ || !reader) return setVolume(std::move(reader));
    reader_ = std::move(reader);
    sampler_.reset();
    cache_ = std::make_unique<core::BrickCache>(std::size_t(256) << 20);
    sampler_ = std::make_unique<core::SliceSampler>(*reader_, *cache_);
    resample();
}

double SliceView::valueAtPoint() const {
    if (!sampler_) return std::nan("");
    const auto& g = reader_->geometry();
    // the voxel under the crosshair as stored, not a blend of its neighbours
    return sampler_->valueAt(g.nearestVoxelCentre(point_), 0) * g.rescaleSlope + g.rescaleIntercept;
}

void SliceView::setVolume(std::shared_ptr<const core::OctreeReader> reader) {
    reader_ = std::move(reader);
    normal_ = glm::dvec3(0.0);  // a tilt belongs to the anatomy it followed: the standard plane again
    followsView_ = false;
    measuring_.reset();  // measurements belong to the volume they were made on
    sampler_.reset();
    cache_.reset();
    if (reader_) {
        cache_ = std::make_unique<core::BrickCache>(std::size_t(256) << 20);
        sampler_ = std::make_unique<core::SliceSampler>(*reader_, *cache_);
        const auto& s = sampler_->space();
        point_ = s.centre();
        volumeCentre_ = point_;
        // Every volume opens with its own window: never the previous volume's.
        const auto& g = reader_->geometry();
        const auto w = core::DisplayWindow::initial(g);
        centre_ = w.centre;
        width_ = std::max(1e-6, w.width);
        windowName_ = QString::fromStdString(w.name);
        windowChosen_ = false;
        presets_ = core::DisplayWindow::presetsFor(g);
    } else {
        presets_.clear();
    }
    resample();
}

void SliceView::setWindow(double centre, double width, const QString& name) {
    centre_ = centre;
    width_ = std::max(1e-6, width);
    windowName_ = name;
    windowChosen_ = true;
    resample();
}

void SliceView::setAutomaticWindow(const core::DisplayWindow& w) {
    if (windowChosen_ || !reader_) return;
    centre_ = w.centre;
    width_ = std::max(1e-6, w.width);
    windowName_ = QString::fromStdString(w.name);
    resample();
}

void SliceView::keyPressEvent(QKeyEvent* e) {
    if (measuring_.key(e)) return;
    if (e->modifiers() & Qt::ControlModifier) {
        switch (e->key()) {
        case Qt::Key_Up: tilt(5, 0); return;
        case Qt::Key_Down: tilt(-5, 0); return;
        case Qt::Key_Left: tilt(0, -5); return;
        case Qt::Key_Right: tilt(0, 5); return;
        default: break;
        }
    }
    switch (e->key()) {
    case Qt::Key_O:
        setFollowsView(false);
        resetTilt();
        emit orientationReset();
        return;
    case Qt::Key_V: setFollowsView(!followsView_); return;
    case Qt::Key_Up: step(1); return;
    case Qt::Key_Down: step(-1); return;
    case Qt::Key_PageUp: step(10); return;
    case Qt::Key_PageDown: step(-10); return;
    case Qt::Key_BracketRight: {  // a thicker slab: 5, 10, 20, 40 mm
        setSlab(slabMm_ <= 0 ? 5.0 : std::min(slabMm_ * 2, 320.0), slabMode_);
        return;
    }
    case Qt::Key_BracketLeft: setSlab(slabMm_ <= 5.0 ? 0.0 : slabMm_ / 2, slabMode_); return;
    case Qt::Key_M:
        setSlab(slabMm_, slabMode_ == core::SlabMode::Mip     ? core::SlabMode::MinIp
                         : slabMode_ == core::SlabMode::MinIp ? core::SlabMode::Mean
                                                              : core::SlabMode::Mip);
        return;
    default: break;
    }
    const int k = e->key() - Qt::Key_1;
    if (k >= 0 && k < 9 && std::size_t(k) < presets_.size()) {
        const auto& w = presets_[std::size_t(k)];
        setWindow(w.centre, w.width, QString::fromStdString(w.name));
        emit windowChosen(centre_, width_, windowName_);
        return;
    }
    QWidget::keyPressEvent(e);
}

void SliceView::setPoint(const glm::dvec3& patient) {
    point_ = patient;
    resample();
}

core::SlicePlane SliceView::plane() const {
    // The view stays centred on the volume; only the slice follows the point along the normal.
    auto p = glm::length(normal_) > 0
                 ? core::SlicePlane::oblique(normal_, volumeCentre_, pixelMm_, std::max(1, width()), std::max(1, height()))
                 : core::SlicePlane::standard(orientation_, volumeCentre_, pixelMm_, std::max(1, width()),
                                              std::max(1, height()));
    const glm::dvec3 normal = p.normal();
    p.centre = volumeCentre_ + glm::dot(point_ - volumeCentre_, normal) * normal;
    if (reader_) p.centre = reader_->geometry().onNearestLayer(p.centre, normal);  // a native plane shows acquired voxels
    return p;
}

glm::dvec3 SliceView::patientAt(const QPointF& pos) const {
    return plane().patientAt({pos.x(), pos.y()});
}

void SliceView::resizeEvent(QResizeEvent*) { resample(); }

void SliceView::resample() {
    image_ = {};
    if (!sampler_ || width() < 2 || height() < 2) {
        update();
        // Collapsed (a splitter closed on it), it shows nothing, but its plane still moves: the
        // other views' crosshair and the slice scroller follow it.
        if (sampler_) emit resampled();
        return;
    }
    // Fit the volume's extent along the plane's axes into the widget.
    const auto& g = reader_->geometry();
    const glm::dvec3 size = glm::dvec3(g.dims[0], g.dims[1], g.dims[2]) * g.spacing;
    const double extent = std::max({size.x, size.y, size.z});
    pixelMm_ = extent / double(std::min(width(), height()));
    const auto plane = this->plane();
    const auto img = slabMm_ > 0 ? sampler_->sampleSlab(plane, slabMm_, slabMode_) : sampler_->sample(plane);
    level_ = img.level;
    const core::DisplayWindow w{"", centre_, width_};
    if (layers_ && (layers_->hasOverlay() || layers_->hasLabels())) {
        image_ = layers_->compose(img, g, plane, w);
    } else {
        image_ = QImage(img.width, img.height, QImage::Format_Grayscale8);
        const auto grey = core::SliceComposer::grey(img, g, w);
        for (int y = 0; y < img.height; ++y)
            std::copy_n(grey.data() + std::size_t(y) * std::size_t(img.width), std::size_t(img.width), image_.scanLine(y));
    }
    update();
    emit resampled();
}

void SliceView::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), Qt::black);
    if (image_.isNull()) return;
    p.drawImage(0, 0, image_);
    // The cursor at the current point: where the other two planes cut this one, with handles.
    crosshair().paint(p);
    const QRect r = rect().adjusted(5, 3, -5, -3);
    static const char* names[] = {"Axial", "Coronal", "Sagittal"};
    p.setPen(QColor(200, 200, 200));
    QFont info = font();
    info.setPointSizeF(info.pointSizeF() * 0.85);
    p.setFont(info);
    static const char* modes[] = {"MIP", "MinIP", "mean"};
    QString slab = slabMm_ > 0 ? tr("\nslab %1 mm %2").arg(slabMm_, 0, 'g', 4).arg(modes[int(slabMode_)]) : QString();
    if (layers_ && layers_->hasOverlay())
        slab += tr("\n+ %1 (%2, %3 %)").arg(layers_->overlayName(), QString::fromStdString(layers_->overlayMap().name()))
                    .arg(std::lround(layers_->overlayOpacity() * 100));
    if (layers_ && layers_->hasLabels()) slab += tr("\n+ labels %1").arg(layers_->labelsName());
    if (followsView_) slab += tr("\nalong the 3D view");
    else if (const double t = tiltDegrees(); t > 0.05) slab += tr("\ntilted %1\u00b0").arg(t, 0, 'f', 1);
    const QString text = QStringLiteral("%1\n%2\n%3%4\nW %5\nL %6%7")
                             .arg(QString::fromLatin1(names[int(orientation_)]), slicePosition(), levelReadout(), slab)
                             .arg(width_, 0, 'f', 0)
                             .arg(centre_, 0, 'f', 0)
                             .arg(windowName_.isEmpty() ? QString() : QStringLiteral(" (%1)").arg(windowName_));
    // On a dark box: the text stays readable over bright tissue.
    const int flags = Qt::AlignBottom | Qt::AlignLeft;
    p.fillRect(p.boundingRect(r, flags, text).adjusted(-3, -2, 3, 2), QColor(0, 0, 0, 150));
    p.setPen(QColor(200, 200, 200));
    p.drawText(r, flags, text);
    // The orientation letters over everything else ("?" when the orientation is not known: a
    // guess would be worse than none, left is never right), then the notes and measurements.
    p.setFont(font());
    drawEdgeLabels(p, r, edgeLabels());
    drawAssumedGeometry(p, r.adjusted(0, 18, 0, 0), reader_->geometry());
    measuring_.paint(p);
}

void SliceView::mousePressEvent(QMouseEvent* e) {
    pressPos_ = e->position();
    pressCentre_ = centre_;
    pressWidth_ = width_;
    rotating_ = false;
    // A crosshair handle, unless a measurement's handle lies nearer the mouse (or an angle is
    // being placed, or a measurement drawn: those take the press).
    const auto rotation = reader_ && e->button() == Qt::LeftButton && e->modifiers() == Qt::NoModifier && !measuring_.placingAngle()
                              ? crosshair().handleAt(e->position())
                              : std::nullopt;
    const bool rotate = rotation && std::hypot(rotation->x() - e->position().x(), rotation->y() - e->position().y()) <=
                                        measuring_.nearestHandlePx(e->position());
    if (!rotate && measuring_.press(e)) return;  // a measurement's handle, one being drawn, an angle's click
    if (rotate) {
        // The planes turn about where the lines cross (within half a slice of the cursor, on the
        // layers shown): the cursor moves there first, so that it stays where they cross.
        point_ = patientAt(crosshair().centre());
        emit pointChanged(point_);
        update();
        const QPointF v = e->position() - widgetAt(point_);
        rotating_ = true;
        rotateAngle_ = std::atan2(v.y(), v.x());
        return;
    }
    if (e->button() == Qt::LeftButton) {
        point_ = patientAt(e->position());
        emit pointChanged(point_);
        resample();
    }
}

void SliceView::mouseMoveEvent(QMouseEvent* e) {
    if (rotating_) {
        const QPointF v = e->position() - widgetAt(point_);
        if (std::hypot(v.x(), v.y()) < 3.0) return;  // too near the centre to say which way
        const double angle = std::atan2(v.y(), v.x());
        double delta = angle - rotateAngle_;
        while (delta > M_PI) delta -= 2 * M_PI;
        while (delta < -M_PI) delta += 2 * M_PI;
        rotateAngle_ = angle;
        // A screen angle (y down) turns about the normal one way or the other, as right x down is
        // the normal or its opposite.
        const auto pl = plane();
        const double sign = glm::dot(glm::cross(pl.right, pl.down), pl.normal()) < 0 ? -1.0 : 1.0;
        emit rotateRequested(pl.normal(), glm::degrees(delta) * sign);
        return;
    }
    if (measuring_.move(e)) return;
    if (e->buttons() & Qt::RightButton) {  // window/level: horizontal width, vertical level
        const QPointF d = e->position() - pressPos_;
        setWindow(pressCentre_ - d.y() * pressWidth_ / 200.0, pressWidth_ * std::pow(2.0, d.x() / 150.0));
        emit windowChosen(centre_, width_, windowName_);
    } else if (e->buttons() & Qt::LeftButton) {
        point_ = patientAt(e->position());
        emit pointChanged(point_);
        resample();
    }
}

void SliceView::wheelEvent(QWheelEvent* e) { step(e->angleDelta().y() > 0 ? 1 : -1); }

double SliceView::sliceStepMm() const {
    if (!reader_) return 1.0;
    const auto& g = reader_->geometry();
    const glm::dvec3 n = plane().normal();
    double mm = 0;
    for (int a = 0; a < 3; ++a) mm += std::abs(glm::dot(n, g.direction[a])) * g.spacing[a];
    return mm;
}

void SliceView::step(int slices) {
    if (!reader_) return;
    point_ += plane().normal() * sliceStepMm() * double(slices);
    emit pointChanged(point_);
    resample();
}

void SliceView::tilt(double aboutHorizontal, double aboutVertical) {
    const auto p = plane();
    glm::dvec3 n = p.normal();
    const auto rotate = [](const glm::dvec3& v, const glm::dvec3& axis, double degrees) {
        const double a = glm::radians(degrees), c = std::cos(a), s = std::sin(a);
        return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1 - c);
    };
    n = rotate(n, p.right, aboutHorizontal);
    n = rotate(n, p.down, aboutVertical);
    normal_ = glm::normalize(n);
    resample();
}

void SliceView::resetTilt() {
    normal_ = glm::dvec3(0.0);
    resample();
}

double SliceView::tiltDegrees() const {
    const auto standard = core::SlicePlane::standard(orientation_, volumeCentre_, 1, 2, 2);
    return glm::degrees(std::acos(std::clamp(std::abs(glm::dot(standard.normal(), plane().normal())), 0.0, 1.0)));
}

QStringList SliceView::edgeLabels() const {
    if (reader_ && reader_->geometry().orientationAssumed) return {"?", "?", "?", "?"};
    const auto l = plane().edgeLabels();
    return {QString::fromStdString(l[0]), QString::fromStdString(l[1]), QString::fromStdString(l[2]),
            QString::fromStdString(l[3])};
}

void SliceView::setSlab(double mm, core::SlabMode mode) {
    slabMm_ = std::max(0.0, mm);
    slabMode_ = mode;
    resample();
}

int SliceView::nearestAxis() const {
    const auto& g = reader_->geometry();
    const glm::dvec3 n = plane().normal();
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (std::abs(glm::dot(n, g.direction[a])) > std::abs(glm::dot(n, g.direction[axis]))) axis = a;
    return axis;
}

int SliceView::sliceCount() const { return reader_ ? int(reader_->geometry().dims[std::size_t(nearestAxis())]) : 0; }

int SliceView::sliceIndex() const {
    if (!reader_) return 0;
    const glm::dvec3 index(glm::inverse(reader_->geometry().indexToPatient()) * glm::dvec4(point_, 1.0));
    return int(std::lround(index[nearestAxis()]));
}

void SliceView::goToSlice(int index) {
    if (!reader_) return;
    const int steps = std::clamp(index, 0, sliceCount() - 1) - sliceIndex();
    // Along the normal, one step a slice: the slice's sign follows the normal's along the axis.
    const double sign = glm::dot(plane().normal(), reader_->geometry().direction[nearestAxis()]) < 0 ? -1.0 : 1.0;
    if (steps != 0) step(int(sign) * steps);
}

QString SliceView::slicePosition() const {
    if (!reader_) return {};
    const auto& g = reader_->geometry();
    const glm::dvec3 n = plane().normal();
    const int axis = nearestAxis();
    const long slice = sliceIndex() + 1;
    // The patient axis the normal runs along, and the coordinate on it of the cursor on the plane
    // shown (a native plane lies on the nearest voxel layer, up to half a slice from the cursor).
    int patientAxis = 0;
    for (int a = 1; a < 3; ++a)
        if (std::abs(n[a]) > std::abs(n[patientAxis])) patientAxis = a;
    const auto p = plane();
    const glm::dvec3 onPlane = point_ - n * glm::dot(n, point_ - p.centre);
    return tr("slice %1/%2 \u2022 %3 mm").arg(slice).arg(g.dims[std::size_t(axis)]).arg(onPlane[patientAxis], 0, 'f', 1);
}

QString SliceView::levelReadout() const {
    if (!reader_) return {};
    return level_ == 0 ? tr("full resolution") : tr("level %1 of %2").arg(level_).arg(reader_->levelCount() - 1);
}

glm::dvec3 SliceView::normal() const { return plane().normal(); }

void SliceView::setNormal(const glm::dvec3& normal) {
    const glm::dvec3 n = glm::length(normal) > 0 ? glm::normalize(normal) : glm::dvec3(0.0);
    if (glm::length(n - normal_) < 1e-12) return;  // the camera did not turn: nothing to sample again
    normal_ = n;
    resample();
}

void SliceView::setFollowsView(bool on) {
    if (on == followsView_) return;
    followsView_ = on;
    emit followViewToggled(on);
    update();
}

void SliceView::setCrossPlanes(const core::SlicePlane& first, const core::SlicePlane& second) {
    const SliceCrosshair::Other a{first.normal(), first.centre}, b{second.normal(), second.centre};
    if (cross_[0] == a && cross_[1] == b) return;
    cross_[0] = a;
    cross_[1] = b;
    update();
}

SliceCrosshair SliceView::crosshair() const { return {plane(), point_, cross_[0], cross_[1]}; }

std::vector<QPointF> SliceView::crosshairAnchors() const { return reader_ ? crosshair().anchors() : std::vector<QPointF>{}; }

QPointF SliceView::crosshairCentre() const { return crosshair().centre(); }

std::vector<QPointF> SliceView::rotationHandles() const { return reader_ ? crosshair().handles() : std::vector<QPointF>{}; }

std::string SliceView::viewName() const {
    static const char* names[3] = {"axial", "coronal", "sagittal"};
    return std::string(names[int(orientation_)]) + (tiltDegrees() > 0.01 ? " (tilted)" : "");
}

void SliceView::mouseReleaseEvent(QMouseEvent* e) {
    rotating_ = false;
    measuring_.release(e);
}

QPointF SliceView::widgetAt(const glm::dvec3& patient) const {
    const glm::dvec2 p = plane().pixelOf(patient);
    return {p.x, p.y};
}

bool SliceView::onThisSlice(const glm::dvec3& patient) const {
    // Within half a slice along the normal (a region snapped to the slice shown is on it).
    const auto p = plane();
    return std::abs(glm::dot(patient - p.centre, p.normal())) <= 0.5 * sliceStepMm() + 1e-6;
}

}  // namespace hvx::ui
