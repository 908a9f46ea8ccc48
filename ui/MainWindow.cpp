#include "ui/MainWindow.h"
#include "ui/CinePanel.h"

#include "core/appearance/LabelTable.h"

#include <glm/gtc/matrix_transform.hpp>

#include <QAction>
#include <QPlainTextEdit>
#include <QDialog>
#include <QCloseEvent>
#include <QDockWidget>
#include <QFile>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QVBoxLayout>
#include <QInputDialog>
#include <QKeySequence>
#include <QMenuBar>
#include <QStatusBar>
#include <QLabel>
#include <QMessageBox>
#include <QScrollArea>
#include <QGuiApplication>
#include <QScreen>
#include <QSettings>



#include "core/base/Error.h"
#include "dicom/PacsSettings.h"
#include "dicom/StudyDatabase.h"
#include "ui/JobManager.h"
#include "ui/JobsPanel.h"
#include "ui/LightFieldPanel.h"
#include "ui/PacsPanel.h"
#include "ui/RenderControls.h"
#include "ui/CropControls.h"
#include "ui/MeasurementsPanel.h"
#include "dicom/LibraryVersions.h"
#include "ui/SliceScroller.h"
#include "ui/SliceView.h"
#include "ui/FusionLink.h"
#include "ui/SplitVoxelLink.h"
#include "ui/ReconstructionComparison.h"
#include "ui/SliceLayers.h"
#include "ui/LayersPanel.h"
#include "ui/StudyBrowser.h"
#include "ui/TransferFunctionEditor.h"
#include "ui/ToolsPanel.h"
#include "ui/VolumeView.h"
#include "ui/WindowSession.h"
#include "core/reference/SliceSampler.h"

namespace hvx::ui {


MainWindow::MainWindow(QString databasePath, QString pacsSettingsPath, QWidget* parent)
    : QMainWindow(parent), jobs_(std::make_unique<JobManager>()), view_(new VolumeView(this)), readouts_(new QLabel) {
    setWindowTitle(tr("Holovox"));
    setObjectName("mainWindow");
    if (databasePath.isEmpty()) databasePath = QString::fromStdString(dicom::StudyDatabase::defaultPath());
    if (pacsSettingsPath.isEmpty()) pacsSettingsPath = QString::fromStdString(dicom::PacsSettings::defaultPath());
    dbPath_ = databasePath;
    pacsConfigPath_ = pacsSettingsPath;
    setCentralWidget(view_);
    setDockNestingEnabled(true);

    browser_ = new StudyBrowser(*jobs_, databasePath);
    browser_->setPacsSettingsPath(pacsSettingsPath);
    pacs_ = new PacsPanel(*jobs_, pacsSettingsPath, databasePath);
    jobsPanel_ = new JobsPanel(*jobs_);
    tfEditor_ = new TransferFunctionEditor;
    controls_ = new RenderControls;
    crop_ = new CropControls;
    measurements_ = new MeasurementsPanel;
    auto* slicesWidget = new QWidget;
    auto* slicesLayout = new QHBoxLayout(slicesWidget);
    slicesLayout->setContentsMargins(2, 2, 2, 2);
    for (int i = 0; i < 3; ++i) {
        slices_[i] = new SliceView(core::SlicePlane::Orientation(i));
        scrollers_[i] = new SliceScroller(slices_[i]);
        auto* column = new QVBoxLayout;
        column->setSpacing(1);
        column->addWidget(slices_[i], 1);
        column->addWidget(scrollers_[i]);
        slicesLayout->addLayout(column);
    }
    layers_ = new SliceLayers(this);
    for (auto* s : slices_) s->setLayers(layers_);
    layersPanel_ = new LayersPanel(*layers_);
    auto* fusion = new FusionLink(*layers_, *view_, this);  // the layers' partner in the 3D view too
    connect(layersPanel_, &LayersPanel::show3DToggled, fusion, &FusionLink::setEnabled);
    connect(fusion, &FusionLink::failed, this, [this](const QString& text) { statusBar()->showMessage(text, 8000); });
    layersPanel_->setJobs(jobs_.get(), browser_->databasePath());
    splitLink_ = new SplitVoxelLink(*controls_, *view_, *jobs_, this);  // trilinear, nearest or split-voxels per volume
    connect(controls_, &RenderControls::compareRequested, this, [this] {
        if (!reader_ || !view_->hasVolume()) return showError(tr("Open a volume first: the comparison draws it."));
        auto* dialog = new ReconstructionComparison(*view_, *splitLink_, reader_, this);
        dialog->setAttribute(Qt::WA_DeleteOnClose);
        dialog->show();
    });
    auto* studies = addDock(tr("Studies"), "studiesDock", browser_, Qt::LeftDockWidgetArea);
    auto* pacsDock = addDock(tr("PACS"), "pacsDock", pacs_, Qt::LeftDockWidgetArea);
    tabifyDockWidget(studies, pacsDock);
    studies->raise();
    auto* tfDock = addDock(tr("Transfer function"), "tfDock", tfEditor_, Qt::RightDockWidgetArea);
    auto* renderDock = addDock(tr("Rendering"), "renderDock", controls_, Qt::RightDockWidgetArea, true);
    // Tools and output of later work, present so the layout is stable.
    toolPanels_[0] = new ToolsPanel(ToolsPanel::Section::Probes);
    toolPanels_[1] = new ToolsPanel(ToolsPanel::Section::Clip);
    toolPanels_[2] = new ToolsPanel(ToolsPanel::Section::Band);
    auto* probes = addDock(tr("Probes"), "probesDock", toolPanels_[0], Qt::RightDockWidgetArea, true);
    auto* clip = addDock(tr("Clip plane"), "clipDock", toolPanels_[1], Qt::RightDockWidgetArea, true);
    auto* band = addDock(tr("Band picker"), "bandDock", toolPanels_[2], Qt::RightDockWidgetArea, true);
    auto* cropDock = addDock(tr("Crop"), "cropDock", crop_, Qt::RightDockWidgetArea, true);
    lightField_ = new LightFieldPanel(*view_);
    lightField_->setJobs(jobs_.get());
    auto* lf = addDock(tr("Light field"), "lightFieldDock", lightField_, Qt::RightDockWidgetArea, true);
    tabifyDockWidget(renderDock, probes);
    tabifyDockWidget(probes, clip);
    tabifyDockWidget(clip, cropDock);
    tabifyDockWidget(cropDock, band);
    tabifyDockWidget(band, lf);
    auto* layersDock = addDock(tr("Layers"), "layersDock", layersPanel_, Qt::RightDockWidgetArea, true);
    tabifyDockWidget(lf, layersDock);
    cine_ = new CinePanel;
    auto* cineDock = addDock(tr("Cine"), "cineDock", cine_, Qt::RightDockWidgetArea, true);
    tabifyDockWidget(layersDock, cineDock);
    connect(cine_, &CinePanel::timePointChosen, this, &MainWindow::showTimePoint);
    renderDock->raise();
    (void)tfDock;
    auto* slicesDock = addDock(tr("Slices"), "slicesDock", slicesWidget, Qt::BottomDockWidgetArea);
    auto* jobsDock = addDock(tr("Jobs"), "jobsDock", jobsPanel_, Qt::BottomDockWidgetArea);
    auto* measurementsDock = addDock(tr("Measurements"), "measurementsDock", measurements_, Qt::BottomDockWidgetArea);
    tabifyDockWidget(jobsDock, measurementsDock);
    jobsDock->raise();
    statusBar()->addPermanentWidget(jobsPanel_->statusWidget());
    statusBar()->addPermanentWidget(readouts_);
    buildMenus();

    connect(browser_, &StudyBrowser::openSeries, this, &MainWindow::openSeries);
    connect(browser_, &StudyBrowser::overlaySeries, this, [this, layersDock](const QString& uid, const QString& octree,
                                                                            const QString& label, int volume) {
        layersDock->show();
        layersDock->raise();
        layersPanel_->overlaySeries(uid, octree, label, volume);
    });
    connect(browser_, &StudyBrowser::imported, this, [this](const QString& s) { statusBar()->showMessage(tr("Imported: %1").arg(s), 8000); });
    connect(browser_, &StudyBrowser::studyRemoved, this, [this](const QString& s) { statusBar()->showMessage(s, 8000); });
    connect(browser_, &StudyBrowser::failed, this, &MainWindow::showError);
    connect(pacs_, &PacsPanel::retrieved, browser_, &StudyBrowser::refresh);
    connect(tfEditor_, &TransferFunctionEditor::changed, this, &MainWindow::applyTransferFunction);
    connect(tfEditor_, &TransferFunctionEditor::failed, this, &MainWindow::showError);
    for (auto* s : slices_) {
        connect(s, &SliceView::measured, this, [this](const core::Measurement& m) { measurements_->add(m); });
        connect(s, &SliceView::removeRequested, this, [this](const std::string& label) { measurements_->remove(label); });
        connect(s, &SliceView::edited, this, [this](const core::Measurement& m) { measurements_->replace(m); });
        connect(measurements_, &MeasurementsPanel::regionShapeChosen, s, &SliceView::setRegionShape);
    }
    connect(measurements_, &MeasurementsPanel::changed, this, [this] {
        for (auto* s : slices_) s->setMeasurements(measurements_->list().items());
        view_->setMeasurements(measurements_->list().items());
        if (!measurementsKey_.isEmpty())  // kept per volume with the session
            QSettings().setValue("measurements/" + measurementsKey_,
                                 QString::fromStdString(measurements_->list().toJson(core::MeasurementSource{})));
    });
    connect(view_, &VolumeView::cropDragged, crop_, &CropControls::setBox);
    connect(crop_, &CropControls::changed, this, [this] {
        view_->setRenderSettings(renderSettings());
        view_->setCropEditing(crop_->isOn());
        if (!openPath_.isEmpty()) {  // the crop box is kept per volume
            const auto b = crop_->box();
            QSettings().setValue("crop/" + openPath_, QStringList{QString::number(b.min.x, 'g', 17), QString::number(b.min.y, 'g', 17),
                                                                  QString::number(b.min.z, 'g', 17), QString::number(b.max.x, 'g', 17),
                                                                  QString::number(b.max.y, 'g', 17), QString::number(b.max.z, 'g', 17)});
        }
    });
    connect(controls_, &RenderControls::changed, this, [this] {
        view_->setRenderSettings(renderSettings());
        view_->setAccuracy(controls_->accuracy());
        view_->setFrameReconstruction(controls_->frameReconstruction());
    });
    view_->setFrameReconstruction(controls_->frameReconstruction());
    connect(controls_, &RenderControls::refractionChanged, this, &MainWindow::applyTransferFunction);
    connect(view_, &VolumeView::frameRendered, this, &MainWindow::updateReadouts);
    connect(view_, &VolumeView::failed, this, &MainWindow::showError);
    connect(jobs_.get(), &JobManager::finished, this, [this](int, const QString& state, const QString& message) {
        if (state == "failed") showError(message);
    });
    for (auto* panel : toolPanels_) connect(panel, &ToolsPanel::changed, this, &MainWindow::applyTools);
    connect(view_, &VolumeView::surfacePicked, this, &MainWindow::placeTool);
    connect(view_, &VolumeView::measured, this, [this](const core::Measurement& m) { measurements_->add(m); });
    connect(view_, &VolumeView::hint, this, [this](const QString& text) { statusBar()->showMessage(text, 8000); });
    connect(view_, &VolumeView::frameRendered, this, [this] {  // slices along the 3D view follow its camera
        for (auto* s : slices_)
            if (s->followsView()) s->setNormal(view_->camera().back());
    });
    connect(view_, &VolumeView::toolsEdited, this, [this](const core::ToolSet& t) {
        tools_ = t;
        for (auto* panel : toolPanels_) panel->setTools(tools_);
    });
    for (auto* s : slices_) {
        // Dragging a crosshair's handle turns the other two planes about this one's normal (they
        // stay perpendicular to each other); O puts all three back on the acquisition axes.
        connect(s, &SliceView::rotateRequested, this, [this, s](const glm::dvec3& axis, double degrees) {
            const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), glm::radians(degrees), axis);
            for (auto* other : slices_)
                if (other != s) other->setNormal(glm::dvec3(turn * glm::dvec4(other->normal(), 0.0)));
        });
        connect(s, &SliceView::followViewToggled, this, [this, s](bool on) {
            if (on) s->setNormal(view_->camera().back());  // seen from where the 3D view sees
        });
        connect(s, &SliceView::orientationReset, this, [this] {
            for (auto* other : slices_) {
                other->setFollowsView(false);
                other->resetTilt();
            }
        });
        connect(s, &SliceView::resampled, this, [this] {
            for (int k = 0; k < 3; ++k) slices_[k]->setCrossPlanes(slices_[(k + 1) % 3]->plane(), slices_[(k + 2) % 3]->plane());
        });
        connect(s, &SliceView::pointChanged, this, [this, s](const glm::dvec3& p) {
            for (auto* other : slices_)
                if (other != s) other->setPoint(p);
        });
        // One window for the three views, remembered per volume for the next time it opens.
        connect(s, &SliceView::windowChosen, this, [this, s](double centre, double width, const QString& name) {
            for (auto* other : slices_)
                if (other != s) other->setWindow(centre, width, name);
            if (!openPath_.isEmpty())
                QSettings().setValue("windows/" + openPath_, QStringList{QString::number(centre, 'g', 17),
                                                                        QString::number(width, 'g', 17), name});
        });
    }

    // A first run takes the screen's available size (a saved geometry replaces it), the slice
    // views two fifths of its height and three fifths of its width beside the jobs, the side
    // docks a fifth of its width each (340 px at least: the browser's columns and date fields).
    const QScreen* screen = QGuiApplication::primaryScreen();
    const QRect available = screen ? screen->availableGeometry() : QRect(0, 0, 1400, 900);
    resize(available.size());
    move(available.topLeft());
    resizeDocks({slicesDock}, {available.height() * 2 / 5}, Qt::Vertical);
    resizeDocks({slicesDock, jobsDock}, {available.width() * 3 / 5, available.width() * 2 / 5}, Qt::Horizontal);
    const int side = std::max(340, available.width() / 5);
    resizeDocks({studies, tfDock}, {side, side}, Qt::Horizontal);
    for (const QString& message : WindowSession::restore(*this)) showError(message);
    statusBar()->showMessage(tr("Ready"));
}

MainWindow::~MainWindow() { jobs_->waitIdle(0); }

QDockWidget* MainWindow::addDock(const QString& title, const QString& name, QWidget* widget, Qt::DockWidgetArea area,
                                 bool scrolled) {
    auto* dock = new QDockWidget(title, this);
    dock->setObjectName(name);
    if (scrolled) {  // long forms scroll instead of making the window taller than the screen
        auto* scroll = new QScrollArea;
        scroll->setWidgetResizable(true);
        scroll->setFrameShape(QFrame::NoFrame);
        scroll->setWidget(widget);
        dock->setWidget(scroll);
    } else {
        dock->setWidget(widget);
    }
    addDockWidget(area, dock);
    docks_ << dock;
    return dock;
}

void MainWindow::buildMenus() {
    QMenu* file = menuBar()->addMenu(tr("&File"));
    QAction* open = file->addAction(tr("&Open volume\u2026"), this, &MainWindow::chooseOpen);
    open->setShortcut(QKeySequence::Open);
    open->setToolTip(tr("Open a Holovox .hvo octree, a NIfTI, NRRD, MetaImage or VTK volume, or a DICOM file"));
    QAction* import = file->addAction(tr("&Import folder / DICOMDIR\u2026"), this, &MainWindow::chooseImport);
    import->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_I));
    QAction* shot = file->addAction(tr("Save &screenshot\u2026"), this, &MainWindow::saveScreenshot);
    shot->setShortcut(QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S));
    file->addSeparator();
    QAction* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
    quit->setShortcut(QKeySequence::Quit);

    QMenu* viewMenu = menuBar()->addMenu(tr("&View"));
    using S = core::OrbitCamera::Standard;
    const std::pair<QString, S> standards[] = {{tr("&Anterior"), S::Anterior}, {tr("&Posterior"), S::Posterior},
                                               {tr("&Left"), S::Left},         {tr("&Right"), S::Right},
                                               {tr("&Superior"), S::Superior}, {tr("&Inferior"), S::Inferior}};
    for (const auto& [name, s] : standards) viewMenu->addAction(name, this, [this, s = s] { view_->setStandardView(s); });
    QAction* reset = viewMenu->addAction(tr("Reset view"), view_, &VolumeView::resetView);
    reset->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_R));
    viewMenu->addSeparator();
    for (auto* d : docks_) viewMenu->addAction(d->toggleViewAction());

    QMenu* help = menuBar()->addMenu(tr("&Help"));
    help->addAction(tr("&Job log"), this, [this] {  // every finished job's whole outcome
        QFile f(JobsPanel::logPath());
        const QString text = f.open(QIODevice::ReadOnly | QIODevice::Text) ? QString::fromUtf8(f.readAll())
                                                                            : tr("No job has finished yet.");
        auto* dialog = new QDialog(this);
        dialog->setWindowTitle(tr("Job log \u2014 %1").arg(JobsPanel::logPath()));
        dialog->setObjectName("jobLog");
        dialog->setAttribute(Qt::WA_DeleteOnClose);
        auto* view = new QPlainTextEdit(text, dialog);
        view->setReadOnly(true);
        view->moveCursor(QTextCursor::End);
        auto* layout = new QVBoxLayout(dialog);
        layout->addWidget(view);
        dialog->resize(900, 500);
        dialog->open();
    });
    help->addAction(tr("&About Holovox"), this, [this] { QMessageBox::about(this, tr("About Holovox"), aboutText()); });
}

QString MainWindow::aboutText() const {
    QString libraries = QStringLiteral("Qt %1").arg(QString::fromLatin1(qVersion()));
    for (const auto& [name, version] : dicom::LibraryVersions::all())
        libraries += QStringLiteral(", %1 %2").arg(QString::fromStdString(name), QString::fromStdString(version));
    const QString gl = view_->glRenderer().isEmpty() ? tr("(no OpenGL context yet)") : view_->glRenderer();
    return tr("Holovox %1 \u2014 out-of-core volume ray casting for medical imaging.\n"
              "Not for diagnostic use unless validated for it at your site.\n\n"
              "Libraries: %2.\nOpenGL: %3.\n\n"
              "Study database: %4\nPACS settings: %5\nSettings: %6")
        .arg(QCoreApplication::applicationVersion(), libraries, gl, dbPath_, pacsConfigPath_,
             QSettings().fileName());
}

core::RenderSettings MainWindow::renderSettings() const {
    auto rs = controls_->settings();
    rs.crop = crop_->box();
    return rs;
}

void MainWindow::applyTransferFunction() {
    if (!reader_) return;
    try {
        const auto& g = reader_->geometry();
        // A label map is drawn in its table's colours, each label whole (no editor ramp that
        // would blend two labels into a third's colour).
        tfEditor_->setEnabled(!g.isLabel);
        tfEditor_->setToolTip(g.isLabel ? tr("A label map is drawn with its label table, one colour per label.") : QString());
        if (g.isLabel)
            return view_->setTransferFunction(core::TransferFunction::forLabels(
                core::LabelTable::forLabelMap(reader_->path(), g.valueMin, g.valueMax), 1.0, referenceLength_));
        auto tf = tfEditor_->transferFunction(referenceLength_);
        // The dock's one number draws ν by opacity in place of the editor's own curve; the
        // editor's row shows what is drawn.
        if (const double nu = controls_->refractionIndex(); nu > 1.0) {
            tf.setRefraction(tf.refractionByOpacity(nu));
            tfEditor_->showRefractionSetElsewhere(
                tr("Refraction %1 by opacity, set in the Rendering dock: set it to 1.00 there to draw this row's own curve")
                    .arg(nu, 0, 'f', 2),
                tf.refraction());
        } else {
            tfEditor_->showRefractionSetElsewhere({}, {});
        }
        view_->setTransferFunction(tf);
    } catch (const core::Error& e) {
        showError(QString::fromStdString(e.what()));
    }
}

void MainWindow::setTools(const core::ToolSet& tools) {
    tools.validate();
    tools_ = tools;
    for (auto* panel : toolPanels_) panel->setTools(tools_);
    view_->setTools(tools_);
}

void MainWindow::applyTools() {
    core::ToolSet t = tools_;
    for (auto* panel : toolPanels_) panel->apply(t);
    try {
        view_->setTools(t);
        tools_ = t;
    } catch (const core::Error& e) {
        showError(QString::fromStdString(e.what()));
        for (auto* panel : toolPanels_) panel->setTools(tools_);  // refuse: back to the last valid values
    }
}

void MainWindow::placeTool(const glm::dvec3& patient, bool alt) {
    core::ToolSet t = tools_;
    if (alt && reader_) {
        // The band around the value under the cursor: grown over the histogram while the bins
        // stay above a third of the picked bin's count (region growing, as Huang's band picker).
        core::BrickCache cache(32u << 20);
        const core::SliceSampler sampler(*reader_, cache);
        auto plane = core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, patient, 0.1, 1, 1);
        const float v = sampler.sample(plane, 0).values[0];
        if (std::isnan(v)) return;
        const auto [lo, hi] = histogram_.bandAround(v);
        const double ramp = std::max(1.0, 0.25 * (hi - lo));
        t.band.enabled = true;
        t.band.band = {lo - ramp, lo, hi, hi + ramp};
        t.band.axis = -glm::normalize(view_->camera().back());
        statusBar()->showMessage(tr("Band picked around %1: [%2, %3]").arg(v).arg(lo).arg(hi), 5000);
    } else {
        t.focal.centre = patient;
        t.context.centre = patient;
        t.context.axis = -glm::normalize(view_->camera().back());
        if (!t.focal.enabled && !t.context.enabled) t.focal.enabled = true;
    }
    setTools(t);
}

void MainWindow::showError(const QString& message) {
    lastError_ = message;
    statusBar()->showMessage(message, 15000);
}

void MainWindow::showNotice(const QString& message) {
    lastNotice_ = message;
    statusBar()->showMessage(message, 30000);
}

void MainWindow::updateReadouts() {
    const auto& r = view_->readouts();
    readouts_->setText(tr("%1 fps \u2022 %2 bricks \u2022 cache %3/%4 MiB%5")
                           .arg(r.fps, 0, 'f', 1)
                           .arg(r.residentBricks)
                           .arg(double(r.cacheBytes) / double(1 << 20), 0, 'f', 0)
                           .arg(double(r.cacheBudget) / double(1 << 20), 0, 'f', 0)
                           .arg(r.resolution < 1.0 ? tr(" \u2022 interactive") : QString()));
}

void MainWindow::saveScreenshot() {
    if (!view_->hasVolume()) return showError(tr("Open a volume first"));
    const QString path = QFileDialog::getSaveFileName(this, tr("Save screenshot"), {}, tr("PNG image (*.png);;OpenEXR (*.exr)"));
    if (path.isEmpty()) return;
    bool ok = false;
    const QString size = QInputDialog::getText(this, tr("Screenshot size"), tr("Width x height:"), QLineEdit::Normal,
                                               QStringLiteral("%1x%2").arg(view_->width()).arg(view_->height()), &ok);
    if (!ok) return;
    const auto parts = size.split('x');
    try {
        if (parts.size() != 2) throw core::Error("the size must be WIDTHxHEIGHT, e.g. 1920x1080");
        view_->capture(path, parts[0].toInt(), parts[1].toInt());
        statusBar()->showMessage(tr("Saved %1").arg(path), 5000);
    } catch (const core::Error& e) {
        showError(QString::fromStdString(e.what()));
    }
}

void MainWindow::closeEvent(QCloseEvent* e) {
    WindowSession::save(*this);
    e->accept();
}

}  // namespace hvx::ui
