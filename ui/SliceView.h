#pragma once
#include <QImage>
#include <QWidget>

#include <memory>

#include <glm/vec3.hpp>

#include "core/streaming/BrickCache.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/SliceSampler.h"

namespace hvx::ui {

/// One 2D slice view (axial, coronal or sagittal) through the current point, read from the
/// octree at the level matching its pixels, with window/level (right drag), a cursor linked to
/// the other views (click or drag sets the point; the wheel steps through slices) and
/// orientation labels. For orientation, not a full MPR suite.
///
/// Threading: GUI thread only.
class SliceView : public QWidget {
    Q_OBJECT
public:
    SliceView(core::SlicePlane::Orientation orientation, QWidget* parent = nullptr);
    void setVolume(std::shared_ptr<const core::OctreeReader> reader);
    /// Window centre and width in physical units (HU for CT).
    void setWindow(double centre, double width);
    double windowCentre() const { return centre_; }
    double windowWidth() const { return width_; }
    void setPoint(const glm::dvec3& patient);
    const glm::dvec3& point() const { return point_; }
    /// The last sampled image (grey, without overlays) and its octree level.
    const QImage& image() const { return image_; }
    int level() const { return level_; }
    /// Patient position under a widget position.
    glm::dvec3 patientAt(const QPointF& pos) const;

signals:
    void pointChanged(const glm::dvec3& patient);

protected:
    void paintEvent(QPaintEvent*) override;
    void resizeEvent(QResizeEvent*) override;
    void mousePressEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void wheelEvent(QWheelEvent* e) override;

private:
    core::SlicePlane plane() const;
    void resample();

    core::SlicePlane::Orientation orientation_;
    std::shared_ptr<const core::OctreeReader> reader_;
    std::unique_ptr<core::BrickCache> cache_;
    std::unique_ptr<core::SliceSampler> sampler_;
    glm::dvec3 point_{0.0};
    glm::dvec3 volumeCentre_{0.0};
    double pixelMm_ = 1.0;
    double centre_ = 40, width_ = 400;
    QImage image_;
    int level_ = 0;
    QPointF pressPos_;
    double pressCentre_ = 0, pressWidth_ = 0;
};

}  // namespace hvx::ui
