#pragma once
#include <QElapsedTimer>
#include <QImage>
#include <QOpenGLWidget>
#include <QTimer>

#include <memory>
#include <optional>
#include <vector>

#include "core/reference/CpuRayCaster.h"
#include "core/base/JobContext.h"
#include "core/reference/MeasurementList.h"
#include "ui/CropBoxHandles.h"
#include "core/camera/DisplayModel.h"
#include "core/camera/InteractiveQuality.h"
#include "core/image/FrameReconstructor.h"
#include "core/octree/OctreeReader.h"
#include "core/camera/OrbitCamera.h"
#include "core/appearance/TransferFunction.h"
#include "ui/ToolDragger.h"

namespace hvx::render {
class GpuRayCaster;
}

namespace hvx::ui {

/// The 3D view: a QOpenGLWidget hosting the render module. Each frame refines the working set
/// for the camera, ray casts it on the GPU and shows the image, with patient-orientation labels
/// and an orientation cube. Navigation: left drag rotates (trackball), middle or Shift+left drag
/// pans, right drag or the wheel (or a pinch) zooms; keys A P L R S I pick the standard views,
/// Home resets, the arrows rotate and +/- zoom. While the camera moves, frames are drawn at a
/// reduced resolution and step (core::InteractiveQuality); a still camera gets full quality.
///
/// Threading: GUI thread; GL calls happen only in the widget's context.
class VolumeView : public QOpenGLWidget {
    Q_OBJECT
public:
    struct Readouts {
        double fps = 0, frameMs = 0;
        std::size_t residentBricks = 0, poolSlots = 0, cacheBytes = 0, cacheBudget = 0;
        double resolution = 1.0;
        bool subFrame = false;  ///< the last frame was rebuilt from quincunx sub-frames
        bool complete = false;
        bool settled = false;                      ///< nothing loading: the cut stays while the view does
        int finestLevel = 0, coarsestLevel = 0, levels = 1;  ///< octree levels drawn (0: full resolution)
    };

    explicit VolumeView(QWidget* parent = nullptr);
    /// Asks Qt for the OpenGL 4.5 core profile the render module needs (compute shaders,
    /// direct state access) for every window: call before the QApplication is made.
    static void requestGlFormat();
    ~VolumeView() override;

    /// Shows a volume (framed in the anterior view, or keeping the camera: the full octree
    /// replacing its preview); nullptr clears the view.
    void setVolume(std::shared_ptr<const core::OctreeReader> reader, bool keepCamera = false);
    bool hasVolume() const;
    /// The time points of a 4D series, each its own warm working set (one brick cache each,
    /// sharing the view's budget), `current` shown; a null reader is a time point whose octree
    /// is not built yet (setTimePoint adds it). setVolume() ends them.
    void setTimePoints(std::vector<std::shared_ptr<const core::OctreeReader>> readers, int current);
    void setTimePoint(int index, std::shared_ptr<const core::OctreeReader> reader);
    /// Shows time point `index` with the same camera, transfer function and settings; after
    /// each frame the working sets of its neighbours (index ± 1) are refined for the same view,
    /// so that cine never waits for the disk once warm. False when that time point has no octree yet.
    bool showTimePoint(int index);
    int timePoint() const { return timePoint_; }
    int timePointCount() const { return int(times_.size()); }
    /// Bricks read from disk so far by every time point's loader (the open volume's alone
    /// without time points).
    std::size_t bricksLoaded() const;
    /// A second volume fused over the open one in the same ray march (an overlay under its
    /// colour map, or a label map in its table's colours), with its own working set (the view's
    /// cache budget again) and transfer function. Drawn in DVR without the
    /// illustrative tools (fusedShown() says whether the last frame drew it); setVolume() ends it.
    void setFusedVolume(std::shared_ptr<const core::OctreeReader> reader, const core::TransferFunction& tf);
    void clearFusedVolume();
    bool fusedShown() const { return fusedShown_; }
    /// A split-voxel octree of the open volume (thesis ch. 4), drawn in 3D in its place in DVR
    /// without a fused volume (splitShown() says whether the last frame drew it), through its
    /// own working set; nullptr goes back to the volume's own octree.
    /// setVolume() ends it.
    void setSplitVolume(std::shared_ptr<const core::OctreeReader> reader);
    bool splitShown() const { return splitShown_; }
    void setTransferFunction(const core::TransferFunction& tf);
    void setRenderSettings(const core::RenderSettings& settings);
    const core::RenderSettings& renderSettings() const { return settings_; }
    /// The illustrative tools (DVR); throws core::Error for out-of-range parameters.
    void setTools(const core::ToolSet& tools);
    /// Quality/accuracy: voxels per pixel of the working set (1 = full, larger is coarser).
    void setAccuracy(double voxelsPerPixel);
    double accuracy() const { return accuracy_; }
    /// While the camera moves, each frame draws one quincunx sub-frame and the image is rebuilt
    /// from the last four (thesis §3.3, core::FrameReconstructor) rather than a whole frame at
    /// a lower resolution alone; on by default (hvx_bench_gui compares the two).
    void setFrameReconstruction(bool on);
    bool frameReconstruction() const { return quality_.options().subFrames; }
    void setStandardView(core::OrbitCamera::Standard view);
    void resetView();
    core::OrbitCamera& camera() { return camera_; }

    /// Renders the current view at full quality at width x height and writes a PNG or EXR.
    /// Throws core::Error naming the file on failure.
    void capture(const QString& path, int width, int height);
    /// The current view drawn at full quality at `size` from `reader` (the open volume's octree
    /// or its split-voxel octree) at its level `level` wherever the view reaches it, through a
    /// working set of its own: the thesis's Fig. 4.6 compares reconstructions so. `nearest`:
    /// nearest-neighbour samples (plain octrees). DVR, with the view's tools. Throws core::Error.
    QImage renderLevel(std::shared_ptr<const core::OctreeReader> reader, int level, bool nearest, QSize size);
    /// Renders every view of a multi-view display from one working set with the display's
    /// accuracy s(z) (what the 3D view draws: its fused volume too, or its split-voxels), the
    /// screen centred on the camera's target and facing the camera; `zoom`
    /// scales the volume's default fit. Views are shrunk so the frame holds at most `maxBeams`
    /// rays. `interactive` lowers the sampling rate as the thesis does while moving: pixels of
    /// 2.5 mm on the screen (at least twice the display's own) and a doubled step. Throws
    /// core::Error when no volume is open.
    std::vector<core::RenderImage> renderViews(const core::DisplayModel& display, double eta, double zoom,
                                               double maxBeams = 8e6, bool interactive = false,
                                               core::JobContext* job = nullptr);
    /// The last image shown (the ray-cast frame, without overlays), at the widget's size.
    QImage lastFrame() const { return frame_; }
    int frameCount() const { return frames_; }
    const Readouts& readouts() const { return readouts_; }
    /// D: the next two left clicks on the volume pick a distance's ends on the rendered surface
    /// (the depth the ray caster returned for that pixel); Esc cancels.
    void startDistance();
    bool measuringDistance() const { return picking_ == Picking::Distance; }
    /// B: the next two left clicks pick a sphere's centre and a point of its rim on the rendered
    /// surface; its statistics come from the octree's level 0 (measured); Esc cancels.
    void startSphere();
    bool measuringSphere() const { return picking_ == Picking::Sphere; }
    /// The first significant sample under a widget position in the last frame, if any.
    std::optional<glm::dvec3> surfaceAt(QPointF pos) const;
    /// Shows the crop box (settings' crop) as a wireframe with a handle on each face; dragging a
    /// handle moves that face (cropDragged). On while the crop box is switched on.
    void setCropEditing(bool on);
    /// Widget positions of the crop box's face handles (low i, j, k, then high), when shown.
    std::vector<QPointF> cropHandles() const;
    /// The same handles in patient coordinates (LPS mm): the middles of the box's faces.
    std::vector<glm::dvec3> cropHandlePoints() const;
    /// "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6": the OpenGL renderer and
    /// version of the view's context (empty before it is made).
    const QString& glRenderer() const { return glRenderer_; }
    /// The measurements to draw: those made in the 3D view, projected, with their labels.
    void setMeasurements(std::vector<core::Measurement> items);
    /// Widget position of a patient point in the current view, and its distance along the view
    /// (mm); false when behind the eye.
    bool project(const glm::dvec3& p, QPointF& out, double& depth) const;
    /// The same without the depth: none when the point lies behind the eye.
    std::optional<QPointF> projected(const glm::dvec3& p) const;
    /// The labels drawn at the left, right, top and bottom edges (e.g. "R", "L", "S", "I").
    QStringList orientationLabels() const;
    /// What the last frame drew: "full resolution", "levels 1-3 of 5, as fine as the pixels
    /// show", "… refining…" while bricks load, or "… the brick budget is reached".
    QString levelReadout() const;

signals:
    void frameRendered();
    /// Ctrl+click (or Alt+click) on the volume: the first significant sample under the cursor.
    void surfacePicked(const glm::dvec3& patient, bool alt);
    /// A crop box face was dragged: the box it makes.
    void cropDragged(const hvx::core::CropBox& box);
    /// The probes were moved or scaled in the view (Ctrl+drag, Ctrl+Shift+drag, Ctrl+wheel).
    void toolsEdited(const core::ToolSet& tools);
    void failed(const QString& message);
    /// A distance (D, then two clicks) or a sphere with its statistics (B, then two clicks)
    /// picked in the view, for the measurement list.
    void measured(const hvx::core::Measurement& m);
    /// A word for the status bar ("click on the volume: nothing under the cursor").
    void hint(const QString& message);

protected:
    void initializeGL() override;
    void paintGL() override;
    void mousePressEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void mouseReleaseEvent(QMouseEvent* e) override;
    void wheelEvent(QWheelEvent* e) override;
    void keyPressEvent(QKeyEvent* e) override;
    bool event(QEvent* e) override;

private:
    struct Scene;
    core::RenderImage renderFrame(const core::View& view, const core::RenderSettings& rs, bool converge);
    void paintOverlays(QPainter& p);
    void interacted();

    std::unique_ptr<Scene> scene_;
    std::unique_ptr<Scene> fused_;  // a volume fused over scene_'s (setFusedVolume)
    std::unique_ptr<Scene> split_;  // the open volume as split-voxels (setSplitVolume)
    bool splitShown_ = false;
    /// The scene the last frame drew: split_ when splitShown_, else scene_.
    Scene& drawn() const { return splitShown_ ? *split_ : *scene_; }
    std::unique_ptr<core::TransferFunction> fusedTf_;
    bool fusedShown_ = false;
    /// The other time points' scenes (the shown one's entry is empty: it is scene_).
    std::vector<std::unique_ptr<Scene>> times_;
    int timePoint_ = -1;
    std::unique_ptr<Scene> makeScene(std::shared_ptr<const core::OctreeReader> reader, std::size_t cacheBytes) const;
    void prefetchNeighbours();
    std::unique_ptr<render::GpuRayCaster> gpu_;
    std::unique_ptr<core::TransferFunction> tf_;
    std::unique_ptr<core::TransferFunction> straightTf_;  // tf_ without its refraction, when it has one
    /// The transfer function drawn: tf_, less its refraction where refraction is not drawn (the
    /// tools, a fused volume, split-voxels, a mode other than DVR), said in the readout.
    QString levelOnlyReadout() const;
    const core::TransferFunction& drawnTf(const core::RenderSettings& rs, bool fused, bool split);
    QString refractionOff_;  // why the last frame was drawn without the refraction asked for
    core::RenderSettings settings_;
    core::OrbitCamera camera_;
    core::InteractiveQuality quality_;
    core::FrameReconstructor rebuilt_;  // while moving: the image from the last four sub-frames
    std::uint64_t rebuiltPicture_ = 0;  // numbers what the camera and the cut show
    core::View rebuiltFor_;
    /// A sub-frame of lastView_ into the rebuilt image (its ray counts kept for the feedback).
    core::RenderImage rebuildFrame(core::RenderImage subFrame, int k);
    double accuracy_ = 1.0;
    QImage frame_;
    std::vector<float> lastDepth_;  // of the last frame, at its own (maybe reduced) size
    enum class Picking { None, Distance, Sphere } picking_ = Picking::None;  // D or B: picking points
    bool cropEditing_ = false;
    QString glRenderer_;
    std::optional<int> cropFace_;  // the crop box face being dragged
    core::CropBox cropPress_;      // the box when its drag began
    QPointF cropFrom_;             // where that drag began
    /// The crop box's handles for the open volume and the current camera.
    std::optional<CropBoxHandles> cropHandlesNow() const;
    std::vector<glm::dvec3> picked_;      // the points picked so far
    std::vector<core::Measurement> measurements_;  // to draw (those made in the 3D view)
    core::View lastView_;
    QString error_;
    int frames_ = 0;
    int unsettledFrames_ = 0;
    Readouts readouts_;
    bool dragging_ = false;
    ToolDragger toolDrag_;
    /// The tools changed by a gesture in the view: kept, announced and redrawn.
    void editTools(const core::ToolSet& tools);
    Qt::MouseButton dragButton_ = Qt::NoButton;
    QPoint lastPos_;
    QTimer settle_;     // wheel/keys: moving until it fires
    QTimer refine_;     // keeps drawing while bricks arrive
};

}  // namespace hvx::ui
