#pragma once
#include <QImage>
#include <QWidget>

class QPainter;

#include <memory>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "core/streaming/BrickCache.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/MeasurementList.h"
#include "core/reference/RegionStatistics.h"
#include "core/reference/SliceSampler.h"
#include "core/volume/DisplayWindow.h"
#include "ui/SliceCrosshair.h"
#include "ui/SliceMeasuring.h"

namespace hvx::ui {

class SliceLayers;

/// One 2D slice view (axial, coronal or sagittal) through the current point, read from the
/// octree at the level matching its pixels, with window/level (right drag), a cursor linked to
/// the other views (click or drag sets the point; the wheel steps through slices) and
/// orientation labels. Each volume opens with its own window (core::DisplayWindow::initial:
/// the DICOM's, else CT's W 400 / L 40, else its value range until the histogram's 1st-99th
/// percentile arrives); the number keys pick its presets. Measuring (SliceMeasuring): Shift-drag
/// a distance (mm), Ctrl-drag a region's statistics (circle, ellipse, rectangle or freehand, as
/// setRegionShape says; one slice thick, from the octree's level 0, in HU for CT),
/// Ctrl+Shift-drag a freehand outline's; A then three clicks an angle. Every measurement of the
/// list (setMeasurements) is drawn with its label and handles on the slice it lies on; dragging a
/// handle edits it (edited). Esc cancels the one in progress and hides the statistics, Del asks
/// to remove the newest one on this slice (removeRequested). Up/Down and the
/// wheel step a slice, Page keys ten; ] and [ make a thick slab, M changes its mode; Ctrl+arrows
/// tilt the plane; the crosshair is where the other planes cut this one, and dragging one of its
/// handles asks them to turn about this normal (rotateRequested); O resets (orientationReset).
///
/// Threading: GUI thread only.
class SliceView : public QWidget {
    Q_OBJECT
public:
    SliceView(core::SlicePlane::Orientation orientation, QWidget* parent = nullptr);
    void setVolume(std::shared_ptr<const core::OctreeReader> reader);
    /// Another time point of the same 4D series (the same grid): the plane, point, window and
    /// measurements stay; only the voxels change.
    void showTimePoint(std::shared_ptr<const core::OctreeReader> reader);
    /// The physical value (HU for CT) of the voxel nearest the crosshair's point, as stored
    /// (level 0, never interpolated); NaN outside.
    double valueAtPoint() const;
    /// Window centre and width in physical units (HU for CT); `name` is shown with it (a
    /// preset's), empty for a window dragged by hand.
    void setWindow(double centre, double width, const QString& name = {});
    double windowCentre() const { return centre_; }
    double windowWidth() const { return width_; }
    const QString& windowName() const { return windowName_; }
    /// A window worked out later (the histogram's percentiles): taken only while the user has
    /// not chosen one for this volume.
    void setAutomaticWindow(const core::DisplayWindow& w);
    /// Presets of the open volume, keys 1.. (the DICOM's, then CT's usual ones for CT).
    const std::vector<core::DisplayWindow>& presets() const { return presets_; }
    void setPoint(const glm::dvec3& patient);
    const glm::dvec3& point() const { return point_; }
    /// The volumes laid over the open one (not owned; null: none); their changes redraw the slice.
    void setLayers(SliceLayers* layers);
    /// The last sampled image (grey; RGB with layers laid over it) and its octree level.
    const QImage& image() const { return image_; }
    int level() const { return level_; }
    /// Patient position under a widget position.
    glm::dvec3 patientAt(const QPointF& pos) const;
    /// Widget position of a patient point projected on the current plane.
    QPointF widgetAt(const glm::dvec3& patient) const;
    /// Tilts the plane: `aboutHorizontal` degrees about its horizontal axis, `aboutVertical` about
    /// its vertical one (Ctrl+Up/Down, Ctrl+Left/Right by 5 degrees; O resets). The plane stays
    /// the standard one nearest its normal, seen as a reader expects, with letters for any tilt.
    void tilt(double aboutHorizontal, double aboutVertical);
    /// Back to the standard plane.
    void resetTilt();
    /// The plane's unit normal.
    glm::dvec3 normal() const;
    /// The plane shown: through the point, on the nearest layer of voxels when it is native.
    core::SlicePlane plane() const;
    /// Sets the plane's normal (the other views' crosshair rotation); zero: the standard plane.
    void setNormal(const glm::dvec3& normal);
    /// Whether the plane follows the 3D view's viewing direction (V toggles; O stops it): the
    /// owner sets the normal from the camera (setNormal) while it is on.
    bool followsView() const { return followsView_; }
    void setFollowsView(bool on);
    /// The other two views' planes as they show them: the crosshair draws where they cut this
    /// plane, with a rotation handle on each side of each line.
    void setCrossPlanes(const core::SlicePlane& first, const core::SlicePlane& second);
    /// Widget positions of the rotation handles (two per crosshair line; none without cross planes).
    std::vector<QPointF> rotationHandles() const;
    /// Widget positions where the crosshair's lines pass nearest the cursor (one per line).
    std::vector<QPointF> crosshairAnchors() const;
    /// Where the crosshair's lines cross: the handles turn the other planes about it.
    QPointF crosshairCentre() const;
    /// Degrees between the plane's normal and the standard plane's.
    double tiltDegrees() const;
    /// The orientation letters at the left, right, top and bottom edges ("?" when unknown).
    QStringList edgeLabels() const;
    /// A thick slab (MIP, MinIP or mean over `mm` along the normal); 0 mm: a thin slice. Keys:
    /// ] thicker, [ thinner, M the next mode.
    void setSlab(double mm, core::SlabMode mode);
    double slabMm() const { return slabMm_; }
    core::SlabMode slabMode() const { return slabMode_; }
    /// One slice: the volume's voxel spacing along the view's normal (the wheel, Up/Down; Page
    /// Up/Down step ten).
    double sliceStepMm() const;
    /// How many slices the volume has along the axis nearest the view's normal (0 without a volume).
    int sliceCount() const;
    /// The 0-based slice nearest the plane along that axis.
    int sliceIndex() const;
    /// Moves to a slice (clamped to the volume), as that many steps of the wheel would.
    void goToSlice(int index);
    /// "slice 12/48 \u2022 42.0 mm": the slice nearest the plane along the volume axis closest to
    /// its normal, and the plane's position along its normal (patient mm).
    QString slicePosition() const;
    /// "full resolution" or "level 2 of 5": the octree level the last image was read from.
    QString levelReadout() const;
    /// The distance measured by Shift-drag (mm between its ends), if any.
    std::optional<double> rulerMm() const { return measuring_.rulerMm(); }
    /// The measurements to draw (those of the open volume; each on the slice it lies on).
    void setMeasurements(std::vector<core::Measurement> items) { measuring_.setItems(std::move(items)); }
    /// Starts an angle: the next three clicks place an arm's end, the vertex and the other end.
    void startAngle() { measuring_.startAngle(); }
    /// The points of the angle being placed (empty when none is).
    const std::vector<glm::dvec3>& anglePoints() const { return measuring_.anglePoints(); }
    /// The region measured by Ctrl-drag and its statistics (or why it has none), if any.
    const std::optional<core::MeasureRegion>& roi() const { return measuring_.roi(); }
    const std::optional<core::RegionStatistics>& roiStatistics() const { return measuring_.roiStatistics(); }
    const QString& roiError() const { return measuring_.roiError(); }
    /// The text over the slice for the last region (SliceMeasuring::statisticsText).
    QString roiText() const { return measuring_.statisticsText(); }
    /// What Ctrl-drag draws (a circle at first).
    void setRegionShape(RegionShape shape) { measuring_.setRegionShape(shape); }
    /// Widget positions of the handles of the measurements drawn on this slice.
    std::vector<QPointF> measurementHandles() const { return measuring_.handles(); }

signals:
    void pointChanged(const glm::dvec3& patient);
    /// The image was sampled again (another slice, volume, window, tilt or size), or, while the
    /// view is too small to show one, its plane changed.
    void resampled();
    /// The user chose a window (a drag or a preset key), in physical units.
    void windowChosen(double centre, double width, const QString& name);
    /// A distance, a region or an angle was completed, for the measurement list.
    void measured(const hvx::core::Measurement& m);
    /// A measurement of the list was changed by its handles (same label; a region measured again).
    void edited(const hvx::core::Measurement& m);
    /// Del on the view: the newest measurement drawn on this slice should go.
    void removeRequested(const std::string& label);
    /// A rotation handle was dragged: the other two planes should turn about `axis` (this plane's
    /// normal) by `degrees` (right-handed), so that their lines follow the mouse.
    void rotateRequested(const glm::dvec3& axis, double degrees);
    /// O: every plane back to the acquisition axes.
    void orientationReset();
    /// V: the plane now follows the 3D view's direction (or no longer does).
    void followViewToggled(bool on);

protected:
    void paintEvent(QPaintEvent*) override;
    void resizeEvent(QResizeEvent*) override;
    void mousePressEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void mouseReleaseEvent(QMouseEvent* e) override;
    void wheelEvent(QWheelEvent* e) override;
    void keyPressEvent(QKeyEvent* e) override;

private:
    friend class SliceMeasuring;
    void resample();
    /// Whether a point made on some slice lies on the current one (within half a voxel).
    bool onThisSlice(const glm::dvec3& patient) const;
    /// The volume axis (0, 1, 2) nearest the plane's normal.
    int nearestAxis() const;
    /// Moves the slice `slices` steps along the normal.
    void step(int slices);
    /// The view's name for the measurement list: "axial", "coronal (tilted)", ...
    std::string viewName() const;

    core::SlicePlane::Orientation orientation_;
    std::shared_ptr<const core::OctreeReader> reader_;
    std::unique_ptr<core::BrickCache> cache_;
    std::unique_ptr<core::SliceSampler> sampler_;
    glm::dvec3 point_{0.0};
    glm::dvec3 volumeCentre_{0.0};
    double pixelMm_ = 1.0;
    double centre_ = 40, width_ = 400;
    QString windowName_;
    bool windowChosen_ = false;  // by the user, for this volume
    std::vector<core::DisplayWindow> presets_;
    QImage image_;
    int level_ = 0;
    QPointF pressPos_;
    double pressCentre_ = 0, pressWidth_ = 0;
    glm::dvec3 normal_{0.0};  ///< the plane's normal; zero: the standard plane's
    double slabMm_ = 0;
    core::SlabMode slabMode_ = core::SlabMode::Mip;
    bool rotating_ = false;  // a crosshair handle is being dragged
    SliceCrosshair::Other cross_[2];  // the other views' planes (normal zero: not known)
    double rotateAngle_ = 0;  // screen angle of the handle being dragged, about the cursor (radians)
    /// The crosshair as it is drawn now.
    SliceCrosshair crosshair() const;
    bool followsView_ = false;
    SliceMeasuring measuring_{*this};
    SliceLayers* layers_ = nullptr;
};

}  // namespace hvx::ui
