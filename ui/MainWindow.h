#pragma once
#include <QHash>
#include <QMainWindow>

#include <memory>

#include "core/octree/OctreeReader.h"
#include "core/appearance/ToolSet.h"
#include "core/reference/RenderSettings.h"
#include "core/reference/VolumeHistogram.h"

class QLabel;
class QDockWidget;

namespace hvx::ui {

class JobManager;
class JobsPanel;
class LightFieldPanel;
class PacsPanel;
class RenderControls;
class CropControls;
class CinePanel;
class TimeSeriesLoader;
class MeasurementsPanel;
class SliceView;
class SliceLayers;
class LayersPanel;
class SliceScroller;
class SplitVoxelLink;
class StudyBrowser;
class ToolsPanel;
class TransferFunctionEditor;
class VolumeView;

/// The workstation's main window. It arranges the docks (study browser, PACS, jobs, transfer
/// function, render controls, slices, and the tool and light-field docks) around the 3D view,
/// wires them together, and keeps the layout and preferences in QSettings. The docks implement
/// themselves; this class only connects them. Opening volumes (files, octrees, DICOM series,
/// time points) lives in ui/MainWindowOpen.cpp.
///
/// Threading: GUI thread only.
class MainWindow : public QMainWindow {
    Q_OBJECT
public:
    /// databasePath / pacsSettingsPath: empty for the defaults ($HOLOVOX_DB, $HOLOVOX_PACS_CONFIG).
    explicit MainWindow(QString databasePath = {}, QString pacsSettingsPath = {}, QWidget* parent = nullptr);
    ~MainWindow() override;

    /// Opens what a user names on the command line: an .hvo file, a volume file (NIfTI, NRRD,
    /// MetaImage, VTK), a DICOM folder or DICOMDIR, or a DICOM file (imported, then its series
    /// opened). Returns false with the error shown.
    bool openPath(const QString& path);
    /// Opens a NIfTI, NRRD, MetaImage or VTK volume: its octree is built in the background (kept
    /// beside the study database, reused while the file is unchanged), then opened. `volume` 0
    /// asks which volume of a 4D file (the first when the file holds one); N opens volume N.
    bool openVolumeFile(const QString& path, int volume = 0);
    /// Whether openVolumeFile() reads `path` (by its name).
    static bool isVolumeFile(const QString& path);
    /// Opens an .hvo octree in the 3D and slice views.
    bool openOctree(const QString& path, const QString& label = {}, bool keepCamera = false);
    /// Opens an imported series, building its octree in the background when missing.
    /// `volume` 0: the series' largest volume; N: volume N of a 4D series.
    void openSeries(const QString& seriesUid, const QString& octreePath, const QString& label, int volume = 0);

    VolumeView* view() const { return view_; }
    StudyBrowser* browser() const { return browser_; }
    PacsPanel* pacs() const { return pacs_; }
    JobManager* jobs() const { return jobs_.get(); }
    /// The open volume's reconstruction in 3D and its split-voxel octree.
    SplitVoxelLink* splitVoxels() const { return splitLink_; }
    JobsPanel* jobsPanel() const { return jobsPanel_; }
    TransferFunctionEditor* tfEditor() const { return tfEditor_; }
    RenderControls* renderControls() const { return controls_; }
    CropControls* cropControls() const { return crop_; }
    MeasurementsPanel* measurements() const { return measurements_; }
    LightFieldPanel* lightField() const { return lightField_; }
    SliceView* slice(int i) const { return slices_[i]; }
    /// The volumes laid over the open one in the slices, and their dock.
    SliceLayers* layers() const { return layers_; }
    LayersPanel* layersPanel() const { return layersPanel_; }
    /// The Cine dock: the time points of the open 4D series.
    CinePanel* cine() const { return cine_; }
    /// Shows time point `index` of the open 4D series in the 3D and slice views (camera, plane,
    /// window and transfer function kept); false while its octree is not ready.
    bool showTimePoint(int index);
    /// The slider and cine bar under slice view i.
    SliceScroller* scroller(int i) const { return scrollers_[i]; }
    const QString& openLabel() const { return openLabel_; }
    /// The illustrative tools of the session (saved with the window layout).
    const core::ToolSet& tools() const { return tools_; }
    /// Throws core::Error for out-of-range parameters.
    void setTools(const core::ToolSet& tools);
    ToolsPanel* toolsPanel(int i) const { return toolPanels_[i]; }
    /// The last error shown in the status bar.
    QString lastError() const { return lastError_; }
    /// The last notice shown in the status bar: what an opened file leaves open or assumes.
    QString lastNotice() const { return lastNotice_; }
    /// Help > About's text: the version, the libraries and OpenGL in use, and the data folders.
    QString aboutText() const;

protected:
    void closeEvent(QCloseEvent* e) override;

private:
    /// The rendering dock's settings with the crop box.
    core::RenderSettings renderSettings() const;
    /// The measurement list saved for the volume at `path`, and its patient, study and series.
    void restoreMeasurements(const QString& path);
    QDockWidget* addDock(const QString& title, const QString& name, QWidget* widget, Qt::DockWidgetArea area,
                         bool scrolled = false);
    void buildMenus();
    void applyTransferFunction();
    void applyTools();
    void placeTool(const glm::dvec3& patient, bool alt);
    void showError(const QString& message);
    /// Shows what an opened file leaves open or assumes (its source's warnings) in the status bar.
    void showNotice(const QString& message);
    void updateReadouts();
    void saveScreenshot();
    void chooseImport();
    void chooseOpen();
    /// After opening `path`: when it is one volume of a 4D series, its time points for cine.
    void setUpTimePoints(const QString& path);

    std::unique_ptr<JobManager> jobs_;
    SplitVoxelLink* splitLink_ = nullptr;
    VolumeView* view_;
    StudyBrowser* browser_;
    PacsPanel* pacs_;
    JobsPanel* jobsPanel_;
    TransferFunctionEditor* tfEditor_;
    RenderControls* controls_;
    CropControls* crop_;
    MeasurementsPanel* measurements_;
    QString seriesUid_;  // the series the open volume came from (for the measurements' UIDs)
    QString measurementsKey_;  // the session key of the open volume's measurements
    QHash<QString, QString> seriesOfOctree_;  // octree path -> the series it was built from
    LightFieldPanel* lightField_;
    SliceView* slices_[3];
    SliceLayers* layers_;
    LayersPanel* layersPanel_;
    CinePanel* cine_;
    TimeSeriesLoader* timeLoader_ = nullptr;
    std::vector<std::shared_ptr<const core::OctreeReader>> timeReaders_;  // null: not ready
    QStringList timeNames_;
    QString timeBaseLabel_;  // the series' label, without the time point
    SliceScroller* scrollers_[3];
    QLabel* readouts_;
    std::shared_ptr<const core::OctreeReader> reader_;
    double referenceLength_ = 1.0;
    QString openLabel_, lastError_, lastNotice_;
    QString openPath_;  // the open octree's key in the session: a hash of its absolute path
    QString dbPath_, pacsConfigPath_;  // in use, for Help > About
    QList<QDockWidget*> docks_;
    ToolsPanel* toolPanels_[3] = {};
    core::ToolSet tools_;
    core::VolumeHistogram histogram_;
};

}  // namespace hvx::ui
