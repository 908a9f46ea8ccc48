#pragma once
#include <QObject>
#include <QString>

#include <memory>
#include <optional>

#include "core/octree/OctreeReader.h"

namespace hvx::ui {

class JobManager;
class RenderControls;
class VolumeView;

/// The 3D view's reconstruction, per volume (the Rendering dock's choice; thesis ch. 4): a label
/// map gets split-voxels by default, an image the preset (setting "reconstruction/default",
/// trilinear unless changed), and each volume keeps the choice last made for it. Split-voxels
/// come from a split-voxel octree built once in the background from the open octree's level 0
/// (core::OctreeVoxelSource) into the cache folder, and reused while that octree file is
/// unchanged; until it is ready, and where it cannot be drawn (other modes, tools, a fused
/// volume), the view draws the volume's own octree. A build that fails is said by the Jobs panel
/// and the choice goes back to the volume's default reconstruction without split-voxels.
///
/// Threading: GUI thread only (the build runs as a job).
class SplitVoxelLink : public QObject {
    Q_OBJECT
public:
    SplitVoxelLink(RenderControls& controls, VolumeView& view, JobManager& jobs, QObject* parent = nullptr);
    /// The octree opened in the view (nullptr: none, or a 4D series, which is drawn from its own
    /// octrees), from the file `path`, named `label` in job titles.
    void setVolume(std::shared_ptr<const core::OctreeReader> reader, const QString& path, const QString& label);
    /// Where the split-voxel octree of the octree file `path` is kept (its name follows the
    /// file's path, size and modification time).
    static QString cachePath(const QString& path);
    /// The volume the link serves (null: none, or a 4D series).
    const std::shared_ptr<const core::OctreeReader>& volume() const { return reader_; }
    /// The split-voxel octree of the open volume, once built or found (null before).
    std::shared_ptr<const core::OctreeReader> splitReader() const { return split_; }
    /// Makes the split-voxel octree of the open volume available without choosing it: opens the
    /// cached file, or starts its build (ready() says when).
    void prepare();

signals:
    /// The open volume's split-voxel octree is ready (and shown, if still chosen).
    void ready();

private:
    void apply();
    void build();

    RenderControls& controls_;
    VolumeView& view_;
    JobManager& jobs_;
    std::shared_ptr<const core::OctreeReader> reader_, split_;
    QString path_, key_, label_;
    int job_ = -1;  // the build running for reader_, if any
    std::optional<int> applied_;  // the reconstruction last applied to reader_ (RenderControls::Reconstruction)
};

}  // namespace hvx::ui
