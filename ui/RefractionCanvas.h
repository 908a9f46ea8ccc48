#pragma once
#include "ui/CurveRowCanvas.h"

#include <vector>

#include "core/appearance/TransferFunction.h"
#include "core/reference/VolumeHistogram.h"

namespace hvx::ui {

/// The transfer-function editor's refraction row (thesis §3.2.2, Figs 3.4–3.5): the refraction
/// index ν over the volume's values (physical units across, as the opacity curve above; ν from
/// kMin to kMax up, 1 dashed when there is no curve) over the log histogram of the values. Edits
/// as every CurveRowCanvas; the curve in stored units. While the Rendering dock's one-number
/// refraction is on, the row shows the curve it draws, read-only.
///
/// Threading: GUI thread only.
class RefractionCanvas : public CurveRowCanvas {
    Q_OBJECT
public:
    static constexpr double kMin = 0.5, kMax = 2.0;  ///< ν across the row's height
    explicit RefractionCanvas(QWidget* parent = nullptr);
    /// The value range the row spans (stored units), the rescale shown in its labels, and the
    /// volume's value histogram.
    void setVolume(double valueMin, double valueMax, double slope, double intercept, const core::VolumeHistogram& histogram);
    /// The curve in stored units (empty: none).
    void setPoints(const std::vector<core::TransferFunction::RefractionPoint>& storedUnits);
    std::vector<core::TransferFunction::RefractionPoint> points() const;
    /// Shows a curve set elsewhere without taking edits (empty `why`: editable again).
    void showFixed(const QString& why, const std::vector<core::TransferFunction::RefractionPoint>& storedUnits);

protected:
    QString leftLabel() const override;
    QString rightLabel() const override;

private:
    double slope_ = 1.0, intercept_ = 0.0;
};

}  // namespace hvx::ui
