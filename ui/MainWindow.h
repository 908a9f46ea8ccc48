#pragma once
#include <QMainWindow>

class QPlainTextEdit;

namespace hvx::ui {

/// The workstation's main window. For now it opens .hvo octrees and shows their summary;
/// the study browser, PACS panel, jobs and 3D view dock into it in later issues.
///
/// Threading: GUI thread only.
class MainWindow : public QMainWindow {
    Q_OBJECT
public:
    explicit MainWindow(QWidget* parent = nullptr);
    /// Opens an .hvo file and shows its summary; shows the error in the window otherwise.
    bool openOctree(const QString& path);

private:
    void chooseFile();
    QPlainTextEdit* summary_;
};

}  // namespace hvx::ui
