#pragma once
#include <QWidget>

#include "core/appearance/TransferFunctionSpec.h"
#include "core/reference/VolumeHistogram.h"

namespace hvx::ui {

/// The drawing and mouse handling of the transfer-function editor (see TransferFunctionEditor):
/// histogram, opacity curve with handles, colour bar with stops, window/level drag.
///
/// Threading: GUI thread only.
class TransferFunctionCanvas : public QWidget {
    Q_OBJECT
public:
    explicit TransferFunctionCanvas(QWidget* parent = nullptr);
    void setRange(double valueMin, double valueMax, double slope, double intercept);
    void setHistogram(const core::VolumeHistogram& h);
    /// Sets the curves (stored units); end points are pinned to the value range.
    void setSpec(const core::TransferFunctionSpec& s);
    const core::TransferFunctionSpec& spec() const { return spec_; }

    /// Widget position of a value / opacity, and back (tests drive the mouse with these).
    QPointF opacityPoint(double value, double alpha) const;
    double valueAt(double x) const;
    QRectF curveRect() const;
    QRectF colourRect() const;

signals:
    void edited();

protected:
    void paintEvent(QPaintEvent*) override;
    void mousePressEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void mouseReleaseEvent(QMouseEvent* e) override;
    void mouseDoubleClickEvent(QMouseEvent* e) override;
    void keyPressEvent(QKeyEvent* e) override;

private:
    int opacityHit(const QPointF& p) const;
    int colourHit(const QPointF& p) const;
    void pinEnds();

    core::TransferFunctionSpec spec_;
    core::TransferFunctionSpec dragStart_;
    core::VolumeHistogram histogram_;
    double min_ = 0, max_ = 1, slope_ = 1, intercept_ = 0;
    enum class Drag { None, Opacity, Colour, WindowLevel } drag_ = Drag::None;
    int index_ = -1;
    QPointF pressPos_;
};

}  // namespace hvx::ui
