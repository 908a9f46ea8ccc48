#pragma once
#include <QWidget>

#include <vector>

#include "core/appearance/TransferFunction.h"
#include "core/reference/VolumeHistogram.h"

namespace hvx::ui {

/// The transfer-function editor's third row (MedVis §3.2.1): the log histogram of the volume's
/// gradient magnitudes under the gradient-opacity curve, |∇f| in physical units per mm (HU/mm for
/// CT) across, the opacity scale (0 to 1) up. Click to add a point, drag to move it, right-click
/// to remove it; with no point the curve is flat at 1 (no gradient opacity). Every edit emits
/// edited() with the curve in stored units.
///
/// Threading: GUI thread only.
class GradientOpacityCanvas : public QWidget {
    Q_OBJECT
public:
    explicit GradientOpacityCanvas(QWidget* parent = nullptr);
    /// The volume's rescale slope (|∇f| shown in physical units) and its gradient histogram.
    void setVolume(double slope, const core::VolumeHistogram& histogram);
    /// The curve in stored units per mm (empty: none).
    void setPoints(std::vector<core::TransferFunction::GradientPoint> storedUnits);
    const std::vector<core::TransferFunction::GradientPoint>& points() const { return points_; }
    /// Widget position of a (stored |∇f|, scale) point (tests drive the mouse with it).
    QPointF position(double magnitude, double scale) const;
    /// The largest magnitude across the row (stored units per mm).
    double magnitudeMax() const { return magnitudeMax_; }

signals:
    void edited();

protected:
    void paintEvent(QPaintEvent*) override;
    void mousePressEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void mouseReleaseEvent(QMouseEvent* e) override;

private:
    QRectF area() const;
    int hit(const QPointF& p) const;
    core::TransferFunction::GradientPoint at(const QPointF& p) const;
    void sortPoints();

    std::vector<core::TransferFunction::GradientPoint> points_;
    std::vector<std::uint64_t> counts_;
    double binWidth_ = 1.0, magnitudeMax_ = 100.0, slope_ = 1.0;
    int dragging_ = -1;
};

}  // namespace hvx::ui
