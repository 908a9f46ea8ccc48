#pragma once
#include <QHash>
#include <QIcon>
#include <QWidget>

class QComboBox;
class QLineEdit;
class QTreeWidget;
class QTreeWidgetItem;
class QLabel;

namespace hvx::ui {

class JobManager;

/// The study browser: the local study database as a patient -> study -> series tree, filtered
/// by name or ID (wildcards), date range and modality, with thumbnails of series whose octree
/// exists. Importing folders or DICOMDIRs runs as a background job; double-clicking a series
/// asks to open it.
///
/// Threading: GUI thread; the database is read here and written only by jobs (own connection).
class StudyBrowser : public QWidget {
    Q_OBJECT
public:
    StudyBrowser(JobManager& jobs, QString databasePath, QWidget* parent = nullptr);
    const QString& databasePath() const { return dbPath_; }
    /// Scans and indexes files, folders or DICOMDIRs in the background; returns the job id.
    int importPaths(const QStringList& paths);
    /// Re-reads the database with the current filters.
    void refresh();
    QTreeWidget* tree() const { return tree_; }
    /// The series item of a UID (tests), nullptr when not listed.
    QTreeWidgetItem* seriesItem(const QString& seriesUid) const;
    /// Asks for `item`'s series to be laid over the open volume (its context menu's action).
    void requestOverlay(QTreeWidgetItem* item);
    /// The PACS settings whose storage folder holds received files (default: the user's).
    void setPacsSettingsPath(const QString& path) { pacsSettingsPath_ = path; }
    /// Removes a study in the background (dicom::StudyRemoval: its rows, its received files and
    /// its octrees; imported files stay); returns the job id. A study's context menu asks first.
    int removeStudy(const QString& studyUid);

signals:
    /// octreePath is empty when the series has no octree yet.
    /// `volume` 0 opens the series (its largest volume); N opens volume N of a 4D series.
    void openSeries(const QString& seriesUid, const QString& octreePath, const QString& label, int volume);
    /// "Lay over the open volume" from a series' context menu (arguments as openSeries).
    void overlaySeries(const QString& seriesUid, const QString& octreePath, const QString& label, int volume);
    void imported(const QString& summary);
    /// Import job `jobId` is done: the series it found (SeriesInstanceUIDs), in the order first met.
    void importedSeries(int jobId, const QStringList& seriesUids);
    void failed(const QString& message);
    /// A study was removed: what was forgotten, deleted and kept.
    void studyRemoved(const QString& summary);

private:
    void activated(QTreeWidgetItem* item);
    /// Asks whether to remove a study item's study, saying what goes and what stays.
    void confirmRemoval(QTreeWidgetItem* study);
    /// openSeries' or overlaySeries' arguments of a series item, false for a study item.
    bool seriesOf(QTreeWidgetItem* item, QString& uid, QString& octree) const;

    JobManager& jobs_;
    QString dbPath_;
    QString pacsSettingsPath_;
    QLineEdit* text_;
    QLineEdit* from_;
    QLineEdit* to_;
    QComboBox* modality_;
    QTreeWidget* tree_;
    QLabel* count_;
    QHash<QString, QIcon> thumbnails_;  // by series UID (and octree path)
};

}  // namespace hvx::ui
