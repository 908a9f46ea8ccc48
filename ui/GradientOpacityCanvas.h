#pragma once
#include "ui/CurveRowCanvas.h"

#include <vector>

#include "core/appearance/TransferFunction.h"
#include "core/reference/VolumeHistogram.h"

namespace hvx::ui {

/// The transfer-function editor's gradient-opacity row (MedVis §3.2.1): the log histogram of the
/// volume's gradient magnitudes under the gradient-opacity curve, |∇f| in physical units per mm
/// (HU/mm for CT) across, the opacity scale (0 to 1) up; with no point the curve is flat at 1
/// (no gradient opacity). Edits as every CurveRowCanvas; the curve in stored units.
///
/// Threading: GUI thread only.
class GradientOpacityCanvas : public CurveRowCanvas {
    Q_OBJECT
public:
    explicit GradientOpacityCanvas(QWidget* parent = nullptr);
    /// The volume's rescale slope (|∇f| shown in physical units) and its gradient histogram.
    void setVolume(double slope, const core::VolumeHistogram& histogram);
    /// The curve in stored units per mm (empty: none).
    void setPoints(const std::vector<core::TransferFunction::GradientPoint>& storedUnits);
    std::vector<core::TransferFunction::GradientPoint> points() const;
    /// The largest magnitude across the row (stored units per mm).
    double magnitudeMax() const { return xMax_; }

protected:
    QString leftLabel() const override;
    QString rightLabel() const override;

private:
    double slope_ = 1.0;
};

}  // namespace hvx::ui
