#pragma once
#include <QWidget>

#include <map>

class QTableWidget;
class QProgressBar;
class QLabel;

namespace hvx::ui {

class JobManager;

/// The jobs dock: one row per background job with its title, a progress bar, stage and ETA,
/// and a Cancel button; finished jobs stay listed with their outcome. It also drives a compact
/// progress indicator for the status bar (statusWidget()).
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
};

}  // namespace hvx::ui
