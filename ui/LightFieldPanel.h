#pragma once
#include <QImage>
#include <QWidget>

#include <memory>
#include <vector>

#include "core/reference/CpuRayCaster.h"
#include "core/camera/DisplayModel.h"

class QComboBox;
class QLabel;
class QSlider;
class QDoubleSpinBox;
class QCheckBox;

namespace hvx::ui {

class VolumeView;
class LightFieldWindow;
class LightFieldPreviewWindow;
class JobManager;

/// The light-field dock: choose a display profile, eta (MCOP blend), the scale (depth range
/// follows: where s(z) stays within twice the pixel size), render a frame of all views from
/// one working set through the 3D view's renderer, preview it (what an observer at a chosen
/// position sees on a projector display, the quilt, or the stereo frame) and send it to the
/// full-screen output window on a chosen screen.
///
/// Threading: GUI thread only.
class LightFieldPanel : public QWidget {
    Q_OBJECT
public:
    LightFieldPanel(VolumeView& view, QWidget* parent = nullptr);
    ~LightFieldPanel() override;
    /// Renders all views of the chosen display for the current 3D view; returns false (with
    /// the reason shown) when no volume is open or the profile is bad. `asked` (the Render frame
    /// button): as a job in the Jobs panel, and the preview shown in its own window.
    bool renderFrame(bool interactive = false, bool asked = false);
    /// The Jobs panel's manager, for renders the user asks for.
    void setJobs(JobManager* jobs) { jobs_ = jobs; }
    /// The preview's own window (none before the first asked render).
    LightFieldPreviewWindow* previewWindow() const { return previewWindow_.get(); }
    /// Follow the 3D view: re-render on each of its frames, at the lowered sampling rate while
    /// the camera moves and at full quality once it stops.
    void setFollowView(bool follow);
    /// The display frame (quilt, stereo frame or projector atlas) and the preview image.
    const QImage& frame() const { return frame_; }
    const QImage& preview() const { return preview_; }
    QComboBox* profiles() const { return profiles_; }
    LightFieldWindow* outputWindow() const { return window_.get(); }
    void openOutputWindow();

private:
    void updatePreview();
    void updateDepthRange();

    VolumeView& view_;
    QComboBox* profiles_;
    QSlider* eta_;
    QDoubleSpinBox* zoom_;
    QSlider* observer_;
    QComboBox* screens_;
    QLabel* depth_;
    QLabel* previewLabel_;
    QLabel* status_;
    core::DisplayModel display_;
    std::vector<core::RenderImage> views_;
    QImage frame_, preview_;
    std::unique_ptr<LightFieldWindow> window_;
    QCheckBox* follow_;
    bool lastInteractive_ = false;
    JobManager* jobs_ = nullptr;
    std::unique_ptr<LightFieldPreviewWindow> previewWindow_;
};

}  // namespace hvx::ui
