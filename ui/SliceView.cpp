#include "ui/SliceView.h"

#include "ui/EdgeLabels.h"

#include <QMouseEvent>
#include <QKeyEvent>
#include <QPainter>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace hvx::ui {

SliceView::SliceView(core::SlicePlane::Orientation orientation, QWidget* parent)
    : QWidget(parent), orientation_(orientation) {
    setMinimumSize(120, 120);
    setFocusPolicy(Qt::StrongFocus);
    setToolTip(tr("Click or drag: move the cursor \u2022 Wheel: next slice \u2022 Right drag: window/level\n"
                  "1-9: window presets (the DICOM's, then for CT: brain, subdural, stroke, bone, lung, "
                  "mediastinum, abdomen, liver)"));
}

void SliceView::setVolume(std::shared_ptr<const core::OctreeReader> reader) {
    reader_ = std::move(reader);
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
    auto p = core::SlicePlane::standard(orientation_, volumeCentre_, pixelMm_, std::max(1, width()), std::max(1, height()));
    const glm::dvec3 normal = glm::cross(p.right, p.down);
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
    const auto img = sampler_->sample(plane);
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
}

void SliceView::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), Qt::black);
    if (image_.isNull()) return;
    p.drawImage(0, 0, image_);
    // The cursor at the current point.
    const auto pl = plane();
    const QPointF c(width() / 2.0 + glm::dot(point_ - pl.centre, pl.right) / pl.pixelMm,
                    height() / 2.0 + glm::dot(point_ - pl.centre, pl.down) / pl.pixelMm);
    p.setPen(QPen(QColor(80, 200, 255, 180), 1));
    p.drawLine(QPointF(0, c.y()), QPointF(c.x() - 6, c.y()));
    p.drawLine(QPointF(c.x() + 6, c.y()), QPointF(width(), c.y()));
    p.drawLine(QPointF(c.x(), 0), QPointF(c.x(), c.y() - 6));
    p.drawLine(QPointF(c.x(), c.y() + 6), QPointF(c.x(), height()));
    const auto labels = core::SlicePlane::edgeLabels(orientation_);
    const QRect r = rect().adjusted(5, 3, -5, -3);
    p.setFont(font());
    drawEdgeLabels(p, r, {labels[0], labels[1], labels[2], labels[3]});
    static const char* names[] = {"Axial", "Coronal", "Sagittal"};
    p.setPen(QColor(200, 200, 200));
    QFont info = font();
    info.setPointSizeF(info.pointSizeF() * 0.85);
    p.setFont(info);
    p.drawText(r, Qt::AlignBottom | Qt::AlignLeft,
               QStringLiteral("%1\nW %2\nL %3%4").arg(names[int(orientation_)]).arg(width_, 0, 'f', 0).arg(centre_, 0, 'f', 0)
                   .arg(windowName_.isEmpty() ? QString() : QStringLiteral(" (%1)").arg(windowName_)));
}

void SliceView::mousePressEvent(QMouseEvent* e) {
    pressPos_ = e->position();
    pressCentre_ = centre_;
    pressWidth_ = width_;
    if (e->button() == Qt::LeftButton) {
        point_ = patientAt(e->position());
        emit pointChanged(point_);
        resample();
    }
}

void SliceView::mouseMoveEvent(QMouseEvent* e) {
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

void SliceView::wheelEvent(QWheelEvent* e) {
    const auto p = plane();
    const glm::dvec3 normal = glm::cross(p.right, p.down);
    const double step = reader_ ? std::min({reader_->geometry().spacing.x, reader_->geometry().spacing.y,
                                            reader_->geometry().spacing.z})
                                : 1.0;
    point_ += normal * step * (e->angleDelta().y() > 0 ? 1.0 : -1.0);
    emit pointChanged(point_);
    resample();
}

}  // namespace hvx::ui
