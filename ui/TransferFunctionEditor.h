#pragma once
#include <QWidget>

#include <optional>

#include "core/appearance/TransferFunctionSpec.h"
#include "core/reference/VolumeHistogram.h"

class QComboBox;

namespace hvx::ui {

class GradientOpacityCanvas;
class RefractionCanvas;
class TransferFunctionCanvas;

/// The transfer-function editor dock: a log-scaled histogram of the volume under a
/// piecewise-linear opacity curve (drag points, click to add, right-click or Delete to remove;
/// the end points move only vertically), a colour bar with stops (click to add, double-click for
/// the colour picker, right-click to remove), a window/level drag (middle or Ctrl+drag: left/
/// right shifts, up/down widens or narrows the whole function), presets, load/save, and import
/// of 3D Slicer presets.xml and ParaView colour maps; under them the gradient-opacity row
/// (GradientOpacityCanvas) and the refraction row (RefractionCanvas). Every edit emits changed()
/// at once.
///
/// Threading: GUI thread only.
class TransferFunctionEditor : public QWidget {
    Q_OBJECT
public:
    explicit TransferFunctionEditor(QWidget* parent = nullptr);

    /// A volume's value range (stored units), rescale and histogram; resets to the CT bone
    /// preset where the values are HU, else to the MR default.
    void setVolume(double valueMin, double valueMax, double slope, double intercept, bool hounsfield,
                   const core::VolumeHistogram& histogram);
    /// Applies a built-in preset by name (core::TransferFunction::presetNames()).
    void applyPreset(const QString& name);
    /// The edited curves in stored units.
    const core::TransferFunctionSpec& spec() const;
    void setSpec(const core::TransferFunctionSpec& storedUnits);
    /// The transfer function to render with.
    core::TransferFunction transferFunction(double referenceLength) const;
    TransferFunctionCanvas* canvas() const { return canvas_; }
    GradientOpacityCanvas* gradientCanvas() const { return gradient_; }
    RefractionCanvas* refractionCanvas() const { return refraction_; }
    /// While refraction is set elsewhere (the Rendering dock's one number), the refraction row
    /// shows that curve (stored units) read-only and says `why`; empty `why`: the row edits the
    /// spec's own curve again.
    void showRefractionSetElsewhere(const QString& why, const std::vector<core::TransferFunction::RefractionPoint>& drawn);
    QComboBox* presets() const { return presets_; }

    void load(const QString& path);
    void save(const QString& path) const;
    /// Imports the named preset of a Slicer presets.xml (the first when `name` is empty).
    void importSlicer(const QString& path, const QString& name = {});
    void importParaView(const QString& path);

signals:
    void changed();
    void failed(const QString& message);

private:
    void chooseAndLoad();
    void chooseAndSave();
    void chooseAndImport();

    TransferFunctionCanvas* canvas_;
    GradientOpacityCanvas* gradient_;
    RefractionCanvas* refraction_;
    QComboBox* presets_;
    double slope_ = 1, intercept_ = 0;
};

}  // namespace hvx::ui
