#pragma once
#include <QDialog>

#include <memory>

#include "core/octree/OctreeReader.h"

class QComboBox;
class QLabel;

namespace hvx::ui {

class SplitVoxelLink;
class VolumeView;

/// The thesis's Fig. 4.6 for the open volume: the 3D view's current camera drawn at one voxel
/// size (2, 4, 8 or 16 voxels) three ways, side by side: trilinear and nearest from the volume's
/// own octree at that level, and split-voxels from its split-voxel octree at the level of cells
/// that size (built first when it is not there yet). DVR, with the view's tools.
///
/// Threading: GUI thread only.
class ReconstructionComparison : public QDialog {
    Q_OBJECT
public:
    ReconstructionComparison(VolumeView& view, SplitVoxelLink& link, std::shared_ptr<const core::OctreeReader> reader,
                             QWidget* parent = nullptr);
    /// Voxels per edge of the level compared (2, 4, 8 or 16).
    void setVoxels(int voxels);
    /// The three images of the last comparison (trilinear, nearest, split-voxels), null until drawn.
    QImage image(int i) const;
    int renderedCount() const { return rendered_; }
    /// What the dialog says under the images (what is being built, or why a level is not drawn).
    QString statusText() const;

signals:
    void rendered();

private:
    void render();

    VolumeView& view_;
    SplitVoxelLink& link_;
    std::shared_ptr<const core::OctreeReader> reader_;
    QComboBox* voxels_;
    QLabel* images_[3];
    QLabel* captions_[3];
    QLabel* status_;
    int rendered_ = 0;
};

}  // namespace hvx::ui
