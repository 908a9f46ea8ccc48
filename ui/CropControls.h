#pragma once
#include <array>
#include <cstdint>

#include <QWidget>
#include <glm/glm.hpp>

#include "core/volume/CropBox.h"

class QCheckBox;
class QDoubleSpinBox;
class QLabel;

namespace hvx::ui {

/// The 3D view's crop box, typed in millimetres from the volume's first corner along its own
/// axes i, j, k (each labelled with the anatomical direction it runs towards), with a check box
/// to switch it on and a reset to the whole volume. A box turned inside out or thinner than a
/// voxel is not applied: the last good box stays and the reason is shown under the fields.
///
/// Threading: GUI thread only.
class CropControls : public QWidget {
    Q_OBJECT
public:
    explicit CropControls(QWidget* parent = nullptr);
    /// A new volume: the fields take its extent, the box the whole of it (off).
    void setVolume(const std::array<std::uint32_t, 3>& dims, const glm::dvec3& spacing, const glm::dmat3& direction);
    /// The box to render (the whole volume when off).
    core::CropBox box() const;
    /// Sets the box (as given: the fields show it rounded to their decimals) and switches it on
    /// unless it is the whole volume.
    void setBox(const core::CropBox& box);
    /// Whether the box is switched on (its check box).
    bool isOn() const;
    /// The message under the fields (empty when the typed box is applied).
    QString problem() const;

signals:
    void changed();

private:
    void apply();

    QCheckBox* enabled_;
    std::array<QDoubleSpinBox*, 6> faces_{};  // i low, j low, k low, i high, j high, k high
    std::array<QLabel*, 3> axes_{};
    QLabel* problem_;
    std::array<std::uint32_t, 3> dims_{1, 1, 1};
    glm::dvec3 spacing_{1.0};
    core::CropBox box_;
};

}  // namespace hvx::ui
