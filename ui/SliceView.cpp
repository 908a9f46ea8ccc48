#include "ui/SliceView.h"

#include "ui/EdgeLabels.h"

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
                  "1-9: window presets (the DICOM's, then for CT: brain, subdural, stroke, bone, lung, "
                  "mediastinum, abdomen, liver)"));
}

void SliceView::setVolume(std::shared_ptr<const core::OctreeReader> reader) {
    reader_ = std::move(reader);
    normal_ = glm::dvec3(0.0);  // a tilt belongs to the anatomy it followed: the standard plane again
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
        resetTilt();
        emit orientationReset();
        return;
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
    // The cursor at the current point: where the other two planes cut this one, each line with
    // a rotation handle on either side (plain lines when the others are not known).
    const QPointF c = cursorAt();
    p.setPen(QPen(QColor(80, 200, 255, 180), 1));
    std::vector<QPointF> directions;
    for (const auto& n : cross_)
        if (const auto d = crossDirection(n)) directions.push_back(*d);
    if (directions.size() != 2) directions = {QPointF(1, 0), QPointF(0, 1)};
    const double reach = std::hypot(width(), height());
    for (const QPointF& d : directions) {
        p.drawLine(c + 6 * d, c + reach * d);
        p.drawLine(c - 6 * d, c - reach * d);
    }
    p.setRenderHint(QPainter::Antialiasing);
    p.setBrush(QColor(80, 200, 255, 120));
    for (const QPointF& h : rotationHandles()) p.drawEllipse(h, 4.0, 4.0);
    p.setBrush(Qt::NoBrush);
    p.setRenderHint(QPainter::Antialiasing, false);
    const QRect r = rect().adjusted(5, 3, -5, -3);
    static const char* names[] = {"Axial", "Coronal", "Sagittal"};
    p.setPen(QColor(200, 200, 200));
    QFont info = font();
    info.setPointSizeF(info.pointSizeF() * 0.85);
    p.setFont(info);
    static const char* modes[] = {"MIP", "MinIP", "mean"};
    QString slab = slabMm_ > 0 ? tr("\nslab %1 mm %2").arg(slabMm_, 0, 'g', 4).arg(modes[int(slabMode_)]) : QString();
    if (const double t = tiltDegrees(); t > 0.05) slab += tr("\ntilted %1\u00b0").arg(t, 0, 'f', 1);
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
        for (const QPointF& h : rotationHandles())
            if (std::hypot(h.x() - e->position().x(), h.y() - e->position().y()) <= 7.0) {
                const QPointF v = e->position() - cursorAt();
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
        if (e->modifiers() & Qt::ShiftModifier) {
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
        const QPointF v = e->position() - cursorAt();
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
    normal_ = glm::length(normal) > 0 ? glm::normalize(normal) : glm::dvec3(0.0);
    resample();
}

void SliceView::setCrossNormals(const glm::dvec3& first, const glm::dvec3& second) {
    if (cross_[0] == first && cross_[1] == second) return;
    cross_[0] = first;
    cross_[1] = second;
    update();
}

QPointF SliceView::cursorAt() const { return widgetAt(point_); }

std::optional<QPointF> SliceView::crossDirection(const glm::dvec3& other) const {
    if (glm::length(other) == 0.0) return std::nullopt;
    const auto pl = plane();
    const glm::dvec3 d = glm::cross(pl.normal(), other);
    if (glm::length(d) < 1e-9) return std::nullopt;
    const QPointF s(glm::dot(d, pl.right), glm::dot(d, pl.down));
    const double l = std::hypot(s.x(), s.y());
    if (l < 1e-9) return std::nullopt;
    return s / l;
}

std::vector<QPointF> SliceView::rotationHandles() const {
    std::vector<QPointF> out;
    if (!reader_) return out;
    const QPointF c = cursorAt();
    const double r = 0.35 * std::min(width(), height());
    for (const auto& n : cross_)
        if (const auto d = crossDirection(n)) {
            out.push_back(c + r * *d);
            out.push_back(c - r * *d);
        }
    return out;
}

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
    if (measuring_ == Measuring::Roi && roi_) {
        roi_->radius = glm::length(patientAt(e->position()) - roi_->centre);
        measureRoi();
        if (roiStats_) {  // a circle with its statistics goes to the measurement list
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
    const auto p = plane();
    const auto& g = reader_->geometry();
    return std::abs(glm::dot(patient - p.centre, p.normal())) <= 0.5 * std::min({g.spacing.x, g.spacing.y, g.spacing.z}) + 1e-6;
}

void SliceView::paintMeasurements(QPainter& p) {
    if (!reader_) return;
    const bool assumed = reader_->geometry().spacingAssumed;
    const QString unit = assumed ? tr(" (spacing assumed)") : QString();
    const QColor colour(120, 255, 140);
    // Text on a dark box, so that it reads over bright tissue and never hides under other text.
    const auto boxed = [&](const QRectF& area, int flags, const QString& text) {
        const QRectF used = p.boundingRect(area, flags, text);
        p.fillRect(used.adjusted(-3, -2, 3, 2), QColor(0, 0, 0, 170));
        p.setPen(colour);
        p.drawText(area, flags, text);
    };
    p.setRenderHint(QPainter::Antialiasing);
    paintList(p, colour);
    // What is being drawn now (the list draws it once it is made).
    if (ruler_ && measuring_ == Measuring::Ruler && onThisSlice(ruler_->first)) {
        const QPointF a = widgetAt(ruler_->first), b = widgetAt(ruler_->second);
        p.setPen(QPen(colour, 1.5));
        p.drawLine(a, b);
        p.drawEllipse(a, 2.5, 2.5);
        p.drawEllipse(b, 2.5, 2.5);
        const QPointF mid = (a + b) / 2.0;
        boxed(QRectF(mid.x() - 80, mid.y() - 22, 160, 18), Qt::AlignHCenter | Qt::AlignBottom,
              tr("%1 mm%2").arg(*rulerMm(), 0, 'f', 1).arg(unit));
    }
    if (anglePoints_.size() >= 2) {
        const glm::dvec3 c = anglePoints_.size() >= 3 ? anglePoints_[2] : anglePoints_[1];
        core::Measurement m;
        m.kind = core::Measurement::Kind::Angle;
        m.a = anglePoints_[0], m.b = anglePoints_[1], m.c = c;
        paintAngle(p, m.a, m.b, m.c, anglePoints_.size() >= 3 ? tr("%1\u00b0").arg(m.angleDegrees(), 0, 'f', 1) : QString(),
                   colour);
    }
    if (roi_ && onThisSlice(roi_->centre) && roi_->radius > 0) {
        if (measuring_ == Measuring::Roi) {
            const QPointF c = widgetAt(roi_->centre);
            const double r = roi_->radius / plane().pixelMm;
            p.setPen(QPen(colour, 1.5));
            p.setBrush(Qt::NoBrush);
            p.drawEllipse(c, r, r);
        }
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
        // The statistics at the top left, clear of the orientation letters and the window.
        if (!text.isEmpty())
            boxed(QRectF(6, 22, std::max(80, width() / 2), height() / 2), Qt::AlignLeft | Qt::AlignTop | Qt::TextWordWrap,
                  text);
    }
}

void SliceView::paintList(QPainter& p, const QColor& colour) {
    labels_.clear();
    const double pixelMm = plane().pixelMm;
    const auto label = [&](const QPointF& at, const QString& text) { drawLabel(p, QPointF(at.x() + 6, at.y() - 20), text, colour); };
    for (const auto& m : items_) {
        const QString name = QString::fromStdString(m.label);
        p.setPen(QPen(colour, 1.5));
        p.setBrush(Qt::NoBrush);
        if (m.kind == core::Measurement::Kind::Distance && onThisSlice(m.a)) {
            const QPointF a = widgetAt(m.a), b = widgetAt(m.b);
            p.drawLine(a, b);
            p.drawEllipse(a, 2.5, 2.5);
            p.drawEllipse(b, 2.5, 2.5);
            label((a + b) / 2.0, tr("%1  %2 mm").arg(name).arg(m.lengthMm(), 0, 'f', 1));
        } else if (m.kind == core::Measurement::Kind::Angle && onThisSlice(m.b)) {
            paintAngle(p, m.a, m.b, m.c, tr("%1  %2\u00b0").arg(name).arg(m.angleDegrees(), 0, 'f', 1), colour);
        } else if (m.kind == core::Measurement::Kind::Region && m.region && m.region->kind == core::MeasureRegion::Kind::Disc &&
                   onThisSlice(m.region->centre) && std::abs(std::abs(glm::dot(m.region->normal, plane().normal())) - 1.0) < 1e-6) {
            const QPointF c = widgetAt(m.region->centre);
            const double r = m.region->radius / pixelMm;
            p.drawEllipse(c, r, r);
            QString text = name;
            if (m.stats) {
                const QString u = m.stats->units.empty() ? QString() : QStringLiteral(" ") + QString::fromStdString(m.stats->units);
                text += tr("  mean %1%2").arg(m.stats->mean, 0, 'f', 1).arg(u);
            }
            label(c + QPointF(r * 0.7071, -r * 0.7071), text);
        }
    }
}

void SliceView::paintAngle(QPainter& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                           const QString& text, const QColor& colour) {
    const QPointF pa = widgetAt(a), pb = widgetAt(b), pc = widgetAt(c);
    p.setPen(QPen(colour, 1.5));
    p.setBrush(Qt::NoBrush);
    p.drawLine(pa, pb);
    p.drawLine(pb, pc);
    p.drawEllipse(pa, 2.5, 2.5);
    p.drawEllipse(pb, 2.5, 2.5);
    p.drawEllipse(pc, 2.5, 2.5);
    // The arc between the arms, at the vertex (angles on screen: y grows downwards).
    const QPointF u = pa - pb, v = pc - pb;
    const double lu = std::hypot(u.x(), u.y()), lv = std::hypot(v.x(), v.y());
    if (lu > 1 && lv > 1) {
        const double r = std::min({20.0, lu / 2, lv / 2});
        const double start = std::atan2(-u.y(), u.x()), end = std::atan2(-v.y(), v.x());
        double span = end - start;
        while (span > M_PI) span -= 2 * M_PI;
        while (span < -M_PI) span += 2 * M_PI;
        p.drawArc(QRectF(pb.x() - r, pb.y() - r, 2 * r, 2 * r), int(std::lround(glm::degrees(start) * 16)),
                  int(std::lround(glm::degrees(span) * 16)));
    }
    if (!text.isEmpty()) drawLabel(p, QPointF(pb.x() + 8, pb.y() + 4), text, colour);
}

void SliceView::drawLabel(QPainter& p, QPointF topLeft, const QString& text, const QColor& colour) {
    // On a dark box, moved inside the view when it would run over an edge, and below the
    // labels already drawn that it would cover.
    QRectF used = p.boundingRect(QRectF(topLeft, QSizeF(400, 18)), Qt::AlignLeft | Qt::AlignTop, text);
    const auto inside = [&] {
        const double dx = std::min(0.0, width() - 4.0 - used.right()) + std::max(0.0, 4.0 - used.left());
        const double dy = std::min(0.0, height() - 4.0 - used.bottom()) + std::max(0.0, 4.0 - used.top());
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
    p.fillRect(used.adjusted(-3, -2, 3, 2), QColor(0, 0, 0, 170));
    p.setPen(colour);
    p.drawText(used, Qt::AlignLeft | Qt::AlignTop, text);
}

}  // namespace hvx::ui
