#pragma once
#include <QWidget>

#include "core/reference/CpuRayCaster.h"

class QComboBox;
class QCheckBox;
class QDoubleSpinBox;
class QSlider;

namespace hvx::ui {

/// The 3D view's controls: render mode (DVR, isosurface, MIP, MinIP, X-ray), reconstruction
/// (trilinear, nearest, split-voxels), Phong shading parameters, normal unsharp masking and
/// exaggerated shading, boundary enhancement and view-dependent transparency, refraction,
/// multilevel sampling, the isovalue (physical units) and a quality/accuracy slider.
/// Emits changed() on every edit.
///
/// Threading: GUI thread only.
class RenderControls : public QWidget {
    Q_OBJECT
public:
    explicit RenderControls(QWidget* parent = nullptr);
    /// The value conversion and range of the open volume (for the isovalue field).
    void setVolume(double slope, double intercept, double physicalMin, double physicalMax, bool hounsfield);
    core::RenderSettings settings() const;
    void setSettings(const core::RenderSettings& s);
    /// Voxels per pixel of the working set (quality slider: 1 is full accuracy).
    double accuracy() const;
    void setAccuracy(double voxelsPerPixel);
    QComboBox* mode() const { return mode_; }
    /// How the 3D view reconstructs the volume between its voxels (the thesis's Fig. 4.6):
    /// trilinear, nearest neighbour, or split-voxels (two values and a plane per cell).
    enum class Reconstruction { Trilinear, Nearest, SplitVoxels };
    Reconstruction reconstruction() const;
    /// Sets the choice without emitting changed(); for a label map, trilinear is not offered
    /// (a label is never blended with its neighbour).
    void setReconstruction(Reconstruction r, bool labels);
    QComboBox* reconstructionBox() const { return reconstruction_; }
    /// While the camera moves: rebuild frames from quincunx sub-frames (thesis §3.3) rather
    /// than whole frames at a lower resolution alone. Remembered; off unless chosen.
    bool frameReconstruction() const;
    /// Refraction (thesis §3.2.2): the index what the transfer function shows refracts with
    /// (TransferFunction::refractionByOpacity); 1: none (a transfer function file's own
    /// refraction curve then applies).
    double refractionIndex() const;
    /// Whether multilevel sampling (RenderSettings::multilevel) starts on: remembered once chosen.
    static constexpr bool kMultilevelDefault = true;

signals:
    void changed();
    /// The refraction slider moved (the transfer function changes, not the settings).
    void refractionChanged();
    /// "Compare…": the same level with each reconstruction, side by side.
    void compareRequested();

private:
    /// Checks `box` as QSettings remembers `key` (`fallback` the first time) and remembers each toggle.
    void remember(QCheckBox* box, const QString& key, bool fallback);
    QComboBox* mode_;
    QComboBox* reconstruction_;
    QCheckBox* shading_;
    QCheckBox* subFrames_;
    QCheckBox* multilevel_;  // RenderSettings::multilevel (remembered)
    QDoubleSpinBox *ambient_, *diffuse_, *specular_, *shininess_, *iso_;
    QSlider *boundary_, *viewTransparency_, *quality_;
    QSlider *unsharp_, *exaggerated_;  // multilevel shading (thesis §3.2.2)
    QSlider* refraction_;              // index × 100
    double slope_ = 1, intercept_ = 0;
};

}  // namespace hvx::ui
