#pragma once
#include <QSet>
#include <QWidget>

#include "dicom/PacsSettings.h"

class QCheckBox;
class QComboBox;
class QLineEdit;
class QTreeWidget;
class QTreeWidgetItem;
class QLabel;
class QPushButton;

namespace hvx::ui {

class JobManager;

/// The PACS panel: pick a node, fill in the query (patient, ID, dates with quick ranges,
/// modality, accession), and the study table fills in as C-FIND answers stream; expanding a
/// study lists its series. Retrieve fetches the selected studies or series by the node's
/// method (C-GET or C-MOVE) as background jobs with progress per series, indexing them into the
/// study database and building their octrees. Errors appear in plain words with what to check.
///
/// Threading: GUI thread; network work runs in jobs.
class PacsPanel : public QWidget {
    Q_OBJECT
public:
    PacsPanel(JobManager& jobs, QString settingsPath, QString databasePath, QWidget* parent = nullptr);
    /// Reloads the node list from the settings file.
    void reloadSettings();
    /// Starts a study-level C-FIND with the fields as filled in; returns the job id.
    int search();
    /// Retrieves the selected rows; returns the job ids.
    QList<int> retrieveSelected();
    QTreeWidget* results() const { return results_; }
    QLineEdit* patientField() const { return patient_; }
    QComboBox* nodes() const { return nodes_; }
    QString errorText() const;
    /// The demo archive's state as the panel shows it ("starting…", "ready: …", "stopped",
    /// "failed: why"), with the choice to keep it running when Holovox quits (hidden until the
    /// first status).
    void setDemoStatus(const QString& status);
    QString demoStatus() const;
    /// Whether the user chose to keep the demo archive running after quitting (a setting).
    static bool keepDemoRunning();
    QCheckBox* keepDemoBox() const { return keepDemo_; }

signals:
    void retrieved(const QString& summary);

private:
    void editNode();
    void expandStudy(QTreeWidgetItem* item);
    void applyQuickRange(int index);
    void showError(const QString& message);
    int track(int jobId);

    JobManager& jobs_;
    QString settingsPath_, dbPath_;
    dicom::PacsSettings settings_;
    QComboBox* nodes_;
    QLineEdit* patient_;
    QLineEdit* patientId_;
    QLineEdit* dates_;
    QComboBox* quick_;
    QLineEdit* modality_;
    QLineEdit* accession_;
    QTreeWidget* results_;
    QLabel* status_;
    QLabel* demo_;
    QCheckBox* keepDemo_;
    QSet<int> myJobs_;
};

}  // namespace hvx::ui
