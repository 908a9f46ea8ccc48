#include "ui/MainWindow.h"

#include <QAction>
#include <QApplication>
#include <QFileDialog>
#include <QFontDatabase>
#include <QKeySequence>
#include <QMenuBar>
#include <QPlainTextEdit>
#include <QStatusBar>

#include "core/Error.h"
#include "core/OctreeReader.h"
#include "core/OctreeSummary.h"

namespace hvx::ui {

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), summary_(new QPlainTextEdit(this)) {
    setWindowTitle(tr("Holovox"));
    summary_->setReadOnly(true);
    summary_->setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
    summary_->setPlaceholderText(tr("File \u2192 Open an .hvo octree (Ctrl+O)"));
    setCentralWidget(summary_);
    QMenu* file = menuBar()->addMenu(tr("&File"));
    QAction* open = file->addAction(tr("&Open octree\u2026"), this, &MainWindow::chooseFile);
    open->setShortcut(QKeySequence::Open);
    open->setToolTip(tr("Open a Holovox .hvo multiresolution octree"));
    QAction* quit = file->addAction(tr("&Quit"), qApp, &QApplication::quit);
    quit->setShortcut(QKeySequence::Quit);
    resize(900, 600);
    statusBar()->showMessage(tr("Ready"));
}

void MainWindow::chooseFile() {
    const QString path = QFileDialog::getOpenFileName(this, tr("Open octree"), {}, tr("Holovox octrees (*.hvo)"));
    if (!path.isEmpty()) openOctree(path);
}

bool MainWindow::openOctree(const QString& path) {
    try {
        const auto reader = core::OctreeReader::open(path.toStdString());
        summary_->setPlainText(QString::fromStdString(core::OctreeSummary::of(*reader).format(*reader)));
        statusBar()->showMessage(tr("Opened %1").arg(path));
        setWindowTitle(tr("Holovox \u2014 %1").arg(path));
        return true;
    } catch (const core::Error& e) {
        summary_->setPlainText(QString::fromStdString(e.what()));
        statusBar()->showMessage(tr("Could not open %1").arg(path));
        return false;
    }
}

}  // namespace hvx::ui
