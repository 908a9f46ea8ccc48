#pragma once
#include <QWidget>

#include <memory>

#include "core/reference/LabelStatistics.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QSlider;
class QTreeWidget;

namespace hvx::ui {

class JobManager;
class SliceLayers;

/// The Layers dock: what is laid over the open volume in the slice views and how. Overlay: an
/// octree chosen from disk (or from the Studies browser), its colour map (built in or a .lut /
/// .ctbl file), window and opacity. Labels: a label-map octree, its colour table (ITK-SNAP,
/// FreeSurfer, Slicer, mricron; generated colours otherwise), fill opacity, fill and outline,
/// and a legend whose check boxes hide or show each label. Refusals and notes (another frame
/// of reference, labels missing from the table) are shown under the groups; "in another frame"
/// lays a refused partner over anyway.
///
/// Threading: GUI thread only.
class LayersPanel : public QWidget {
    Q_OBJECT
public:
    explicit LayersPanel(SliceLayers& layers, QWidget* parent = nullptr);
    /// Lays `path` over the open volume (as the "Overlay..." button does, without its dialog);
    /// false with the reason shown when refused.
    bool chooseOverlay(const QString& path, const QString& name = {});
    /// Lays a label map over the open volume (the "Labels..." button without its dialog).
    bool chooseLabels(const QString& path, const QString& name = {});
    /// Loads a colour table for the labels (the "Colour table..." button without its dialog).
    bool chooseLabelTable(const QString& path);
    /// Where series' octrees are built when a series without one is laid over (overlaySeries).
    void setJobs(JobManager* jobs, const QString& databasePath);
    /// Lays an imported series over the open volume (the Studies browser's "Lay over the open
    /// volume", or a segmentation series opened): its octree when it has one, else after
    /// building it in the background (a job); a label map (a SEG's) as labels, else in colour.
    void overlaySeries(const QString& seriesUid, const QString& octreePath, const QString& label, int volume);
    /// Lays an octree over the open volume: as labels when it is a label map, else in colour.
    bool layOver(const QString& octreePath, const QString& label = {});
    /// Computes each label's volume and the open volume's mean and SD over it (a job); the
    /// legend shows them and "Export CSV..." saves them. Returns the job id (-1 without labels).
    int computeStatistics();
    /// Writes the last statistics as CSV (core::LabelStatistics::csv); false with the reason shown.
    bool exportStatistics(const QString& path);
    /// The last statistics (empty rows before any).
    const core::LabelStatistics& statistics() const { return *statistics_; }
    /// The sentence under the groups: the last refusal or note (empty when none).
    QString message() const;

signals:
    /// "Show in the 3D view" was switched (ui::FusionLink follows it).
    void show3DToggled(bool on);

private:
    void refresh();
    void refreshLegend();
    void applyOverlayWindow();
    void show(const QString& text, bool error);

    SliceLayers& layers_;
    JobManager* jobs_ = nullptr;
    QString databasePath_;
    QLabel* overlayName_;
    QComboBox* map_;
    QDoubleSpinBox* overlayWidth_;
    QDoubleSpinBox* overlayLevel_;
    QSlider* overlayOpacity_;
    QPushButton* removeOverlay_;
    QLabel* labelsName_;
    QSlider* labelOpacity_;
    QCheckBox* fill_;
    QCheckBox* outline_;
    QTreeWidget* legend_;
    QPushButton* removeLabels_;
    QPushButton* statisticsButton_;
    QPushButton* exportButton_;
    std::shared_ptr<core::LabelStatistics> statistics_ = std::make_shared<core::LabelStatistics>();
    // The volumes the statistics were computed on: dropped when either changes.
    std::weak_ptr<const core::OctreeReader> statisticsImage_, statisticsLabels_;
    QCheckBox* force_;
    QCheckBox* show3D_;
    QLabel* message_;
    bool updating_ = false;
};

}  // namespace hvx::ui
