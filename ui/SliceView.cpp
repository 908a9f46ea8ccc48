#include "ui/SliceView.h"

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
                  "Shift-drag: distance \u2022 Ctrl-drag: circle statistics \u2022 A, then three clicks: angle\n"
                  "Esc: cancel \u2022 Del: remove the newest measurement on this slice\n"
                  "Drag a crosshair handle: turn the other planes \u2022 V: slice along the 3D view \u2022 O: reset\n"
                  "1-9: window presets (the DICOM's, then for CT: brain, subdural, stroke, bone, lung, "
                  "mediastinum, abdomen, liver)"));
}

void SliceView::setVolume(std::shared_ptr<const core::OctreeReader> reader) {
    reader_ = std::move(reader);
    normal_ = glm::dvec3(0.0);  // a tilt belongs to the anatomy it followed: the standard plane again
    followsView_ = false;
    ruler_.reset();  // measurements belong to the volume they were made on
    roi_.reset();
    items_.clear();
    anglePoints_.clear();
    placingAngle_ = false;
    setMouseTracking(false);
    roiStats_.reset();
    roiError_.clear();
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
    if (e->key() == Qt::Key_Escape || e->key() == Qt::Key_Delete) {
        if (e->key() == Qt::Key_Delete && !placingAngle_ && measuring_ == Measuring::None) {
            // The newest measurement of the list drawn on this slice.
            for (auto it = items_.rbegin(); it != items_.rend(); ++it)
                if (onThisSlice(it->region ? it->region->centre : it->a)) {
                    emit removeRequested(it->label);
                    break;
                }
        }
        ruler_.reset();
        roi_.reset();
        roiStats_.reset();
        roiError_.clear();
        anglePoints_.clear();
        placingAngle_ = false;
        setMouseTracking(false);
        update();
        return;
    }
    if (e->key() == Qt::Key_A && !(e->modifiers() & Qt::ControlModifier)) {
        startAngle();
        return;
    }
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
    return p;
}

glm::dvec3 SliceView::patientAt(const QPointF& pos) const {
    const auto p = plane();
    return p.centre + (pos.x() - p.width / 2.0) * p.pixelMm * p.right + (pos.y() - p.height / 2.0) * p.pixelMm * p.down;
}

void SliceView::resizeEvent(QResizeEvent*) { resample(); }

void SliceView::resample() {
    image_ = {};
    if (!sampler_ || width() < 2 || height() < 2) {
        update();
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
    image_ = QImage(img.width, img.height, QImage::Format_Grayscale8);
    const double lo = centre_ - width_ / 2;
    const bool invert = g.monochrome1;
    for (int y = 0; y < img.height; ++y) {
        auto* row = image_.scanLine(y);
        for (int x = 0; x < img.width; ++x) {
            const float v = img.values[std::size_t(y) * std::size_t(img.width) + std::size_t(x)];
            if (std::isnan(v)) {
                row[x] = 0;
                continue;
            }
            double t = std::clamp((v * g.rescaleSlope + g.rescaleIntercept - lo) / width_, 0.0, 1.0);
            if (invert) t = 1.0 - t;
            row[x] = std::uint8_t(std::lround(t * 255.0));
        }
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
    if (followsView_) slab += tr("\nalong the 3D view");
    else if (const double t = tiltDegrees(); t > 0.05) slab += tr("\ntilted %1\u00b0").arg(t, 0, 'f', 1);
    const QString text = QStringLiteral("%1\n%2 \u2022 %3%4\nW %5\nL %6%7")
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
    paintMeasurements(p);
}

void SliceView::mousePressEvent(QMouseEvent* e) {
    pressPos_ = e->position();
    pressCentre_ = centre_;
    pressWidth_ = width_;
    measuring_ = Measuring::None;
    if (e->button() == Qt::LeftButton && reader_ && e->modifiers() == Qt::NoModifier && !placingAngle_) {
        if (crosshair().handleAt(e->position())) {
            const QPointF v = e->position() - widgetAt(point_);
            measuring_ = Measuring::Rotate;
            rotateAngle_ = std::atan2(v.y(), v.x());
            return;
        }
    }
    if (placingAngle_ && e->button() == Qt::LeftButton && reader_) {
        const glm::dvec3 at = patientAt(e->position());
        if (anglePoints_.empty()) anglePoints_.push_back(at);
        anglePoints_.back() = at;     // the point that followed the mouse is placed here
        anglePoints_.push_back(at);   // and the next one follows the mouse
        if (anglePoints_.size() == 4) {
            core::Measurement m;
            m.kind = core::Measurement::Kind::Angle;
            m.view = viewName();
            m.a = anglePoints_[0];
            m.b = anglePoints_[1];
            m.c = anglePoints_[2];
            anglePoints_.clear();
            placingAngle_ = false;
            setMouseTracking(false);
            if (glm::length(m.a - m.b) > 0.0 && glm::length(m.c - m.b) > 0.0) emit measured(m);  // an arm of no length: nothing
        }
        update();
        return;
    }
    if (e->button() == Qt::LeftButton && reader_ && (e->modifiers() & (Qt::ShiftModifier | Qt::ControlModifier))) {
        const glm::dvec3 at = patientAt(e->position());
        if ((e->modifiers() & Qt::ShiftModifier) && (e->modifiers() & Qt::ControlModifier)) {  // freehand outline
            measuring_ = Measuring::Polygon;
            outline_ = {at};
            roi_.reset();
            roiStats_.reset();
            roiError_.clear();
        } else if (e->modifiers() & Qt::ShiftModifier) {
            measuring_ = Measuring::Ruler;
            ruler_ = std::make_pair(at, at);
        } else {
            measuring_ = Measuring::Roi;
            roi_ = core::MeasureRegion::disc(at, plane().normal(), 0.0, 1.0);
            roiStats_.reset();
            roiError_.clear();
        }
        update();
        return;
    }
    if (e->button() == Qt::LeftButton) {
        point_ = patientAt(e->position());
        emit pointChanged(point_);
        resample();
    }
}

void SliceView::mouseMoveEvent(QMouseEvent* e) {
    if (measuring_ == Measuring::Rotate) {
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
    if (placingAngle_) {
        if (!anglePoints_.empty()) anglePoints_.back() = patientAt(e->position());
        update();
        return;
    }
    if (measuring_ == Measuring::Ruler && ruler_) {
        ruler_->second = patientAt(e->position());
        update();
        return;
    }
    if (measuring_ == Measuring::Roi && roi_) {
        roi_->radius = glm::length(patientAt(e->position()) - roi_->centre);
        update();
        return;
    }
    if (measuring_ == Measuring::Polygon) {  // a corner every 3 px the mouse moves
        if (std::hypot(e->position().x() - widgetAt(outline_.back()).x(), e->position().y() - widgetAt(outline_.back()).y()) >= 3.0)
            outline_.push_back(patientAt(e->position()));
        update();
        return;
    }
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
    // The patient axis the normal runs along, and the point's coordinate on it.
    int patientAxis = 0;
    for (int a = 1; a < 3; ++a)
        if (std::abs(n[a]) > std::abs(n[patientAxis])) patientAxis = a;
    return tr("slice %1/%2 \u2022 %3 mm").arg(slice).arg(g.dims[std::size_t(axis)]).arg(point_[patientAxis], 0, 'f', 1);
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

void SliceView::setCrossNormals(const glm::dvec3& first, const glm::dvec3& second) {
    if (cross_[0] == first && cross_[1] == second) return;
    cross_[0] = first;
    cross_[1] = second;
    update();
}

SliceCrosshair SliceView::crosshair() const { return {plane(), widgetAt(point_), size(), cross_[0], cross_[1]}; }

std::vector<QPointF> SliceView::rotationHandles() const { return reader_ ? crosshair().handles() : std::vector<QPointF>{}; }

std::string SliceView::viewName() const {
    static const char* names[3] = {"axial", "coronal", "sagittal"};
    return std::string(names[int(orientation_)]) + (tiltDegrees() > 0.01 ? " (tilted)" : "");
}

void SliceView::startAngle() {
    if (!reader_) return;
    anglePoints_.clear();
    placingAngle_ = true;
    setMouseTracking(true);  // the arm being placed follows the mouse
    update();
}

void SliceView::setMeasurements(std::vector<core::Measurement> items) {
    items_ = std::move(items);
    update();
}

void SliceView::mouseReleaseEvent(QMouseEvent* e) {
    const std::string view = viewName();
    if (measuring_ == Measuring::Polygon) {  // the outline closes from its last corner to its first
        outline_.push_back(patientAt(e->position()));
        roi_ = core::MeasureRegion::polygon(outline_, plane().normal(), 1.0);
        outline_.clear();
        measureRoi();
    }
    if ((measuring_ == Measuring::Roi || measuring_ == Measuring::Polygon) && roi_) {
        if (measuring_ == Measuring::Roi) {
            roi_->radius = glm::length(patientAt(e->position()) - roi_->centre);
            measureRoi();
        }
        if (roiStats_) {  // a region with its statistics goes to the measurement list
            core::Measurement m;
            m.kind = core::Measurement::Kind::Region;
            m.view = view;
            m.region = *roi_;
            m.stats = *roiStats_;
            emit measured(m);
        }
    } else if (measuring_ == Measuring::Ruler && ruler_ && glm::length(ruler_->second - ruler_->first) > 0.0) {
        core::Measurement m;
        m.kind = core::Measurement::Kind::Distance;
        m.view = view;
        m.a = ruler_->first;
        m.b = ruler_->second;
        emit measured(m);
    }
    measuring_ = Measuring::None;
    update();
}

void SliceView::measureRoi() {
    roiStats_.reset();
    roiError_.clear();
    if (!roi_ || !reader_) return;
    // One slice thick: the voxel spacing along the plane's normal.
    const auto& g = reader_->geometry();
    const glm::dvec3 n = roi_->normal;
    double thickness = 0;
    for (int a = 0; a < 3; ++a) thickness += std::abs(glm::dot(n, g.direction[a])) * g.spacing[a];
    roi_->thickness = thickness;
    // A plane along a voxel layer measures the layer it names ("slice 25/48"): between two
    // layers it would take half of each, or both.
    const int axis = nearestAxis();
    if (std::abs(std::abs(glm::dot(n, g.direction[axis])) - 1.0) < 1e-9) {
        const glm::dvec3 index(glm::inverse(g.indexToPatient()) * glm::dvec4(roi_->centre, 1.0));
        const glm::dvec3 shift = (double(std::lround(index[axis])) - index[axis]) * g.spacing[axis] * g.direction[axis];
        roi_->centre += shift;
        for (auto& corner : roi_->outline) corner += shift;
    }
    try {
        roiStats_ = core::RegionStatistics::compute(*reader_, *roi_);
    } catch (const std::exception& ex) {
        roiError_ = QString::fromStdString(ex.what());
    }
}

std::optional<double> SliceView::rulerMm() const {
    if (!ruler_) return std::nullopt;
    return glm::length(ruler_->second - ruler_->first);
}

QPointF SliceView::widgetAt(const glm::dvec3& patient) const {
    const auto p = plane();
    return {width() / 2.0 + glm::dot(patient - p.centre, p.right) / p.pixelMm,
            height() / 2.0 + glm::dot(patient - p.centre, p.down) / p.pixelMm};
}

bool SliceView::onThisSlice(const glm::dvec3& patient) const {
    // Within half a slice along the normal (a region snapped to the slice shown is on it).
    const auto p = plane();
    return std::abs(glm::dot(patient - p.centre, p.normal())) <= 0.5 * sliceStepMm() + 1e-6;
}

void SliceView::paintMeasurements(QPainter& p) {
    if (!reader_) return;
    const auto pl = plane();
    MeasurementOverlay overlay(p, size(), [this](const glm::dvec3& x) { return widgetAt(x); },
                               [this](const glm::dvec3& x) { return onThisSlice(x); }, pl.normal(), pl.pixelMm);
    // The statistics of the last circle at the top left, clear of the letters and the window.
    if (roi_ && onThisSlice(roi_->centre) && (roi_->radius > 0 || roi_->kind == core::MeasureRegion::Kind::Polygon)) {
        const QString unit = reader_->geometry().spacingAssumed ? tr(" (spacing assumed)") : QString();
        QString text;
        if (roiStats_) {
            const auto& s = *roiStats_;
            const QString u = s.units.empty() ? QString() : QStringLiteral(" ") + QString::fromStdString(s.units);
            text = tr("mean %1%2, SD %3\nmin %4, max %5\n%6 voxels, %7 mm\u00b2%8")
                       .arg(s.mean, 0, 'f', 1).arg(u).arg(s.sd, 0, 'f', 1).arg(s.min, 0, 'g', 6).arg(s.max, 0, 'g', 6)
                       .arg(s.voxels).arg(s.areaMm2, 0, 'f', 1).arg(unit);
            if (!s.note.empty()) text += "\n" + QString::fromStdString(s.note);
        } else if (!roiError_.isEmpty()) {
            text = roiError_;
        }
        if (!text.isEmpty()) overlay.box(QRectF(6, 22, std::max(80, width() / 2), height() / 2), text);
        if (measuring_ == Measuring::Roi) overlay.circle(roi_->centre, roi_->radius, {});
    }
    overlay.list(items_);
    if (outline_.size() >= 2) overlay.outline(outline_, false, {});  // the freehand outline being drawn
    // What is being drawn now (the list draws it once it is made).
    if (ruler_ && measuring_ == Measuring::Ruler && onThisSlice(ruler_->first)) {
        const QString unit = reader_->geometry().spacingAssumed ? tr(" (spacing assumed)") : QString();
        overlay.distance(ruler_->first, ruler_->second, tr("%1 mm%2").arg(*rulerMm(), 0, 'f', 1).arg(unit));
    }
    if (anglePoints_.size() >= 2) {
        core::Measurement m;
        m.kind = core::Measurement::Kind::Angle;
        m.a = anglePoints_[0], m.b = anglePoints_[1], m.c = anglePoints_.size() >= 3 ? anglePoints_[2] : anglePoints_[1];
        overlay.angle(m.a, m.b, m.c, anglePoints_.size() >= 3 ? tr("%1\u00b0").arg(m.angleDegrees(), 0, 'f', 1) : QString());
    }
}

}  // namespace hvx::ui
