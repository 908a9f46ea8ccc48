#pragma once
#include <QWidget>

#include <map>

class QTableWidget;
class QProgressBar;
class QLabel;

namespace hvx::ui {

class JobManager;

/// The jobs dock: one row per background job with its title, a progress bar, stage and ETA,
/// and a Cancel button; finished jobs stay listed with their outcome. A job's whole message is
/// its status cell's tooltip, shown in a window of its own on a double-click (selectable), and
/// copied by the row's context menu or Ctrl+C; every finished job is also written to the job
/// log (logPath(), opened from the Help menu). It also drives a compact progress indicator for
/// the status bar (statusWidget()).
///
/// Threading: GUI thread only.
class JobsPanel : public QWidget {
    Q_OBJECT
public:
    JobsPanel(JobManager& jobs, QWidget* parent = nullptr);
    /// A small label + progress bar for the main window's status bar.
    QWidget* statusWidget() const { return status_; }
    /// The row of a job (tests).
    int rowOf(int id) const;
    /// The text of a cell (tests): column 0 title, 1 progress %, 2 state / ETA.
    QString cellText(int id, int column) const;
    /// The whole outcome of a finished job ("failed: …" with the full message), or its status.
    QString details(int id) const;
    /// Puts a job's title and whole outcome on the clipboard.
    void copyDetails(int id) const;
    /// Opens a window with a job's whole outcome, its text selectable.
    void showDetails(int id);
    /// Where finished jobs are logged: $XDG_DATA_HOME/holovox/jobs.log (or ~/.local/share/…).
    static QString logPath();

private:
    void onStarted(int id, const QString& title);
    void onProgress(int id, double fraction, double eta, const QString& stage);
    void onFinished(int id, const QString& state, const QString& message);
    void updateStatus();

    JobManager& jobs_;
    QTableWidget* table_;
    QWidget* status_;
    QLabel* statusLabel_;
    QProgressBar* statusBar_;
    std::map<int, int> rows_;
    std::map<int, QString> titles_;
    std::map<int, double> fractions_;
    std::map<int, QString> outcomes_;  // of finished jobs, whole
    /// The job of a table row, or -1.
    int idAt(int row) const;
};

}  // namespace hvx::ui
