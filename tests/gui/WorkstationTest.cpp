// GUI smoke tests of the workstation under Xvfb (Qt Test): start the main window, import a
// generated series, open it and wait for the first frame, rotate with synthetic mouse events,
// change the TF preset, switch modes, take screenshots; cancelling a running build from the
// jobs panel; a damaged saved session. Assertions look at pixels. Screenshots are kept under
// <build>/test-artifacts/gui/.
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QDir>
#include <QDockWidget>
#include <QElapsedTimer>
#include <QLineEdit>
#include <QMouseEvent>
#include <QPushButton>
#include <QSettings>
#include <QSet>
#include <QSlider>
#include <QFile>
#include <QGroupBox>
#include <QMessageBox>
#include <QClipboard>
#include <QtMath>
#include <QSpinBox>
#include <QSignalSpy>
#include <QTest>
#include <QTreeWidget>
#include <QTreeWidgetItemIterator>
#include <QWheelEvent>

#include <cmath>
#include <filesystem>

#include "core/octree/OctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/TempDir.h"
#include "tests/gui/GuiTestSupport.h"
#include "ui/JobManager.h"
#include "ui/JobsPanel.h"
#include "ui/LightFieldPanel.h"
#include "ui/LightFieldPreviewWindow.h"
#include "ui/LightFieldWindow.h"
#include "ui/MainWindow.h"
#include "ui/CropControls.h"
#include "ui/RenderControls.h"
#include "ui/SliceView.h"
#include "ui/StudyBrowser.h"
#include "ui/ToolsPanel.h"
#include "core/base/Error.h"
#include "ui/TransferFunctionCanvas.h"
#include "ui/TransferFunctionEditor.h"
#include "ui/VolumeView.h"

using namespace hvx;

namespace {
const QString kArtifacts = test::guiArtifacts();
using test::coverage;
using test::difference;
using test::writeSeries;
}  // namespace

class WorkstationTest : public QObject, test::GuiFixture {
    Q_OBJECT

private slots:
    void initTestCase() { open(); }

    void importsAGeneratedSeriesAndOpensItToAFirstFrame() {
        QElapsedTimer clock;
        clock.start();
        writeSeries(dir_.file("dicom"), "GUI^IMPORT", 3);
        qInfo() << "series written" << clock.elapsed() << "ms";
        QSignalSpy imported(window_->browser(), &ui::StudyBrowser::imported);
        window_->browser()->importPaths({QString::fromStdString(dir_.file("dicom"))});
        QTRY_COMPARE_WITH_TIMEOUT(imported.count(), 1, 60000);
        qInfo() << "imported" << clock.elapsed() << "ms";
        auto* tree = window_->browser()->tree();
        QTreeWidgetItem* series = nullptr;
        for (QTreeWidgetItemIterator it(tree); *it; ++it)
            if (!(*it)->data(0, Qt::UserRole + 1).toString().isEmpty()) series = *it;
        QVERIFY2(series, "the imported series is listed in the study browser");
        QVERIFY2(!series->icon(0).isNull(), "a thumbnail from the DICOM images before any octree exists");
        QVERIFY(tree->topLevelItem(0)->text(0).contains("GUI IMPORT"));
        // The study row's Images column counts its images, as the series row does (one series).
        QCOMPARE(series->parent()->text(3), series->text(3));
        QVERIFY(series->text(3).toInt() > 1);
        // Double-click: the octree is built in the background, then the view opens it.
        tree->scrollToItem(series);
        const QRect r = tree->visualItemRect(series);
        QSignalSpy open(window_->browser(), &ui::StudyBrowser::openSeries);
        QSignalSpy titles(window_.get(), &QWidget::windowTitleChanged);
        QTest::mouseClick(tree->viewport(), Qt::LeftButton, {}, r.center());  // the press an activation needs
        QTest::mouseDClick(tree->viewport(), Qt::LeftButton, {}, r.center());
        QCOMPARE(open.count(), 1);
        QTRY_VERIFY2_WITH_TIMEOUT(view()->hasVolume(), qPrintable(window_->lastError()), 60000);
        // A preview octree (every 4th voxel) is shown first, then the full one replaces it.
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(!window_->openLabel().endsWith("(preview)"), 10000);
        bool previewShown = false;
        for (const auto& t : titles) previewShown |= t.at(0).toString().endsWith("(preview)");
        QVERIFY2(previewShown, "the view showed the preview while the octree was building");
        const QImage first = settledFrame();
        QVERIFY2(coverage(first) > 0.05, "the first frame shows the volume (not blank)");
        QVERIFY(!window_->slice(0)->image().isNull());
        QVERIFY(coverage(window_->slice(0)->image()) > 0.05);
        saveArtifact("opened.png");
    }

    void orientationLabelsAreDrawnInPatientTerms() {
        QCOMPARE(view()->orientationLabels(), (QStringList{"R", "L", "S", "I"}));
        // The labels are painted: label-coloured pixels near the middle of the left edge.
        const QImage shot = view()->grab().toImage();
        int labelPixels = 0;
        for (int y = shot.height() / 2 - 12; y < shot.height() / 2 + 12; ++y)
            for (int x = 0; x < 30; ++x) {
                const QColor c = shot.pixelColor(x, y);
                labelPixels += c.red() > 200 && c.green() > 180 && c.blue() < 170;
            }
        QVERIFY2(labelPixels > 5, "the R label is drawn at the left edge");
    }

    void rotatesWithTheMouse() {
        const QImage before = settledFrame();
        const QPoint c = view()->rect().center();
        QTest::mousePress(view(), Qt::LeftButton, {}, c);
        for (int i = 1; i <= 10; ++i) QTest::mouseMove(view(), c + QPoint(12 * i, 0), 10);
        QTest::mouseRelease(view(), Qt::LeftButton, {}, c + QPoint(120, 0));
        const QImage after = settledFrame();
        QVERIFY2(difference(before, after) > 1.0, "rotating changes the image");
        QVERIFY2(view()->orientationLabels() != (QStringList{"R", "L", "S", "I"}),
                 qPrintable(view()->orientationLabels().join(",") + QStringLiteral(" view %1x%2").arg(view()->width()).arg(view()->height())));
        saveArtifact("rotated.png");
    }

    void changingTheTransferFunctionPresetChangesTheImage() {
        const QImage before = settledFrame();
        auto* presets = window_->tfEditor()->presets();
        presets->setFocus();
        QTest::keyClick(presets, Qt::Key_Down);  // ct-bone -> ct-soft-tissue
        QCOMPARE(presets->currentText(), QString("ct-soft-tissue"));
        const QImage after = settledFrame();
        QVERIFY2(difference(before, after) > 1.0, "the image changes with the transfer function");
        saveArtifact("soft-tissue.png");
    }

    // The transfer-function canvas by mouse and keys: a click on the curve adds a point where it
    // was clicked, a drag raises it (and the image changes), Delete removes it, a right click
    // removes an interior point, and a middle drag shifts every point (window/level).
    void transferFunctionCanvasEditsByMouseAndKeys() {
        auto* canvas = window_->tfEditor()->canvas();
        canvas->show();
        QVERIFY(QTest::qWaitForWindowExposed(canvas->window()));
        const auto original = canvas->spec();
        const QImage before = settledFrame();
        const double lo = original.opacity.front().value, hi = original.opacity.back().value;
        // A value between two existing points, well away from their handles.
        double v = 0;
        for (std::size_t i = 0; i + 1 < original.opacity.size() && v == 0; ++i) {
            const QPointF a = canvas->opacityPoint(original.opacity[i].value, 0);
            const QPointF b = canvas->opacityPoint(original.opacity[i + 1].value, 0);
            if (b.x() - a.x() > 40) v = canvas->valueAt((a.x() + b.x()) / 2);
        }
        QVERIFY2(v != 0, "no gap of 40 px between two opacity points");
        const QPoint at = canvas->opacityPoint(v, 0.1).toPoint();
        QTest::mousePress(canvas, Qt::LeftButton, {}, at);
        QCOMPARE(canvas->spec().opacity.size(), original.opacity.size() + 1);
        const QPoint up = canvas->opacityPoint(v, 0.9).toPoint();
        QMouseEvent move(QEvent::MouseMove, QPointF(up), canvas->mapToGlobal(QPointF(up)), Qt::NoButton, Qt::LeftButton,
                         Qt::NoModifier);
        QApplication::sendEvent(canvas, &move);
        QTest::mouseRelease(canvas, Qt::LeftButton, {}, up);
        bool raised = false;
        for (const auto& p : canvas->spec().opacity)
            raised |= std::abs(p.value - v) < (hi - lo) * 0.02 && std::abs(p.alpha - 0.9) < 0.03;
        QVERIFY2(raised, "the new point sits where the pointer let go (value, opacity 0.9)");
        const QImage edited = settledFrame();
        QVERIFY2(difference(before, edited) > 0.5, "the image follows the edited curve");
        canvas->setFocus();
        QTest::keyClick(canvas, Qt::Key_Delete);  // the point just dragged
        QCOMPARE(canvas->spec().opacity.size(), original.opacity.size());
        // A middle drag (or Ctrl-drag) to the right: every point of the curve moves to higher values.
        const QPoint from = canvas->curveRect().center().toPoint();
        QTest::mousePress(canvas, Qt::MiddleButton, {}, from);
        const QPoint to = from + QPoint(30, 0);
        QMouseEvent shift(QEvent::MouseMove, QPointF(to), canvas->mapToGlobal(QPointF(to)), Qt::NoButton,
                          Qt::MiddleButton, Qt::NoModifier);
        QApplication::sendEvent(canvas, &shift);
        QTest::mouseRelease(canvas, Qt::MiddleButton, {}, to);
        // The ends stay pinned to the value range (a new end point where the curve left it), so
        // compare where the opacity lies: its centroid over the range moved to higher values.
        const auto centroid = [&](const core::TransferFunctionSpec& spec) {
            double sum = 0, weighted = 0;
            for (int i = 0; i <= 1000; ++i) {
                const double x = lo + (hi - lo) * i / 1000.0, a = spec.opacityAt(x);
                sum += a;
                weighted += a * x;
            }
            return weighted / sum;
        };
        const double was = centroid(original), now = centroid(canvas->spec());
        QVERIFY2(now > was + 0.01 * (hi - lo), qPrintable(QString("opacity centroid %1 -> %2").arg(was).arg(now)));
        // Back to the preset for the tests that follow.
        window_->tfEditor()->setSpec(original);
        QCOMPARE(canvas->spec().opacity.size(), original.opacity.size());
    }

    // The crop box from its dock: the upper half along k cut away (the frame changes, less is
    // drawn), a box turned inside out is refused in words and the last good one stays, and the
    // reset brings the whole volume back.
    void cropsTheVolumeFromTheDock() {
        const QImage whole = settledFrame();
        auto* crop = window_->cropControls();
        auto* kHigh = crop->findChild<QDoubleSpinBox*>("cropkHigh");
        auto* iLow = crop->findChild<QDoubleSpinBox*>("cropiLow");
        auto* enabled = crop->findChild<QCheckBox*>("cropEnabled");
        QVERIFY(kHigh && iLow && enabled);
        QVERIFY(!enabled->isChecked());
        QVERIFY(crop->box().whole());
        kHigh->setValue(kHigh->maximum() / 2);
        enabled->setChecked(true);
        QVERIFY(!crop->box().whole());
        QVERIFY(std::abs(crop->box().max.z - 0.5) < 0.01);  // the field holds tenths of a mm
        {  // a micro-CT's 0.05 mm voxels: the fields hold thousandths, a face lands on its voxel
            ui::CropControls fine;
            fine.setVolume({100, 100, 100}, glm::dvec3(0.05), glm::dmat3(1.0));
            auto* high = fine.findChild<QDoubleSpinBox*>("cropkHigh");
            QCOMPARE(high->decimals(), 3);
            high->setValue(2.45);  // 49 voxels of 100
            fine.findChild<QCheckBox*>("cropEnabled")->setChecked(true);
            QVERIFY2(std::abs(fine.box().max.z - 0.49) < 1e-9, qPrintable(QString::number(fine.box().max.z, 'g', 12)));
        }
        const QImage cropped = settledFrame();
        saveArtifact("crop.png");
        QVERIFY2(difference(whole, cropped) > 1.0, "the crop box changes the frame");
        QVERIFY2(coverage(cropped) < coverage(whole), "less of the volume is drawn");
        auto* iHigh = crop->findChild<QDoubleSpinBox*>("cropiHigh");
        iHigh->setValue(iHigh->maximum() / 4);
        iLow->setValue(iHigh->maximum() / 2);  // beyond the high face: inside out
        QVERIFY2(crop->problem().contains("inside out along i"), qPrintable(crop->problem()));
        QCOMPARE(crop->box().min.x, 0.0);  // the last good box stays
        iLow->setValue(0.0);
        QVERIFY(crop->problem().isEmpty());
        // The box in the 3D view: a handle on each face; dragging a high face's handle halfway to
        // the low face's moves that face halfway (the dock's field follows), and dragging it past
        // the low face stops it a voxel short.
        auto* view = window_->view();
        auto handles = view->cropHandles();
        QCOMPARE(handles.size(), std::size_t(6));
        int axis = 0;
        double apart = 0;
        for (int a = 0; a < 3; ++a) {
            const QPointF d = handles[std::size_t(a + 3)] - handles[std::size_t(a)];
            if (std::hypot(d.x(), d.y()) > apart) apart = std::hypot(d.x(), d.y()), axis = a;
        }
        QVERIFY2(apart > 40, qPrintable(QString::number(apart)));
        const core::CropBox before = crop->box();
        // To where the point halfway between the two faces is seen (not the handles' screen
        // midpoint: under perspective the nearer half looks longer).
        const auto points = view->cropHandlePoints();
        QPointF middle;
        double depth = 0;
        QVERIFY(view->project((points[std::size_t(axis)] + points[std::size_t(axis + 3)]) / 2.0, middle, depth));
        test::leftDrag(view, handles[std::size_t(axis + 3)].toPoint(), middle.toPoint());
        const double halfway = (before.min[axis] + before.max[axis]) / 2;
        QVERIFY2(std::abs(crop->box().max[axis] - halfway) < 0.03,
                 qPrintable(QString("face at %1, halfway is %2").arg(crop->box().max[axis]).arg(halfway)));
        auto* field = crop->findChild<QDoubleSpinBox*>(QString("crop%1High").arg(QChar('i' + axis)));
        QVERIFY(std::abs(field->value() - crop->box().max[axis] * field->maximum()) < 0.06);
        settledFrame();
        saveArtifact("crop-handles.png");
        handles = view->cropHandles();
        test::leftDrag(view, handles[std::size_t(axis + 3)].toPoint(),
                       (handles[std::size_t(axis)] * 2 - handles[std::size_t(axis + 3)]).toPoint());
        QVERIFY2(crop->box().max[axis] > crop->box().min[axis], "the face went past the opposite one");
        QVERIFY(crop->problem().isEmpty());
        QTest::mouseClick(crop->findChild<QPushButton*>("cropReset"), Qt::LeftButton);
        QVERIFY(view->cropHandles().empty());
        QVERIFY(crop->box().whole());
        QVERIFY2(difference(whole, settledFrame()) < 1.0, "the reset shows the whole volume again");
    }

    void switchesRenderModes() {
        const QImage dvr = settledFrame();
        auto* mode = window_->renderControls()->mode();
        mode->setFocus();
        QTest::keyClick(mode, Qt::Key_Down);
        QTest::keyClick(mode, Qt::Key_Down);  // DVR -> Isosurface -> MIP
        QCOMPARE(mode->currentIndex(), 2);
        const QImage mip = settledFrame();
        QVERIFY(difference(dvr, mip) > 1.0);
        QVERIFY(coverage(mip) > 0.05);
        int grey = 0, lit = 0;
        for (int y = 0; y < mip.height(); y += 3)
            for (int x = 0; x < mip.width(); x += 3) {
                const QRgb p = mip.pixel(x, y);
                if ((p & 0xFFFFFF) == 0) continue;
                ++lit;
                grey += qRed(p) == qGreen(p) && qGreen(p) == qBlue(p);
            }
        QVERIFY2(grey == lit, "MIP is a grey-scale projection");
        saveArtifact("mip.png");
        QTest::keyClick(mode, Qt::Key_Up);
        QTest::keyClick(mode, Qt::Key_Up);
    }

    void illustrativeToolsChangeTheImageAndSurviveARestart() {
        const QImage plain = settledFrame();
        // Ctrl+click on the volume places the focal probe on the surface under the cursor.
        QTest::mouseClick(view(), Qt::LeftButton, Qt::ControlModifier, view()->rect().center());
        QVERIFY(window_->tools().focal.enabled);
        QVERIFY2(glm::length(window_->tools().focal.centre - window_->tools().context.centre) < 1e-9 &&
                     window_->tools().focal.centre != glm::dvec3(0.0),
                 "the probe moved to the picked surface");
        // Ctrl+wheel scales the probe, Ctrl+drag moves it across the view.
        const double radius = window_->tools().focal.radii.x;
        QWheelEvent wheel(QPointF(view()->rect().center()), view()->mapToGlobal(QPointF(view()->rect().center())), QPoint(),
                          QPoint(0, 120), Qt::NoButton, Qt::ControlModifier, Qt::NoScrollPhase, false);
        QApplication::sendEvent(view(), &wheel);
        QVERIFY(std::abs(window_->tools().focal.radii.x - radius * 1.1) < 1e-6);
        const glm::dvec3 before = window_->tools().focal.centre;
        const QPoint c = view()->rect().center();
        QTest::mousePress(view(), Qt::LeftButton, Qt::ControlModifier, c);
        for (int i = 1; i <= 5; ++i) QTest::mouseMove(view(), c + QPoint(10 * i, 0), 10);
        QTest::mouseRelease(view(), Qt::LeftButton, Qt::ControlModifier, c + QPoint(50, 0));
        QVERIFY2(glm::dot(window_->tools().focal.centre - before, view()->camera().right()) > 1.0,
                 "dragging right moves the probe to the view's right");
        window_->toolsPanel(1)->group("clip")->setChecked(true);  // and the clip plane, from its dock
        QVERIFY(window_->tools().clip.enabled);
        const QImage tools = settledFrame();
        QVERIFY2(difference(plain, tools) > 1.0, "the tools change the image");
        saveArtifact("tools.png");
        // The focal probe's context step is in its dock, shown as the tools hold it and applied
        // from it.
        auto stepped = window_->tools();
        stepped.focal.contextStep = 2;
        window_->setTools(stepped);
        QDoubleSpinBox* step = nullptr;
        for (auto* box : window_->toolsPanel(0)->group("focal")->findChildren<QDoubleSpinBox*>())
            if (box->toolTip().contains("ghosted context")) step = box;
        QVERIFY2(step, "a Context step field in the focal probe's group");
        QCOMPARE(step->value(), 2.0);
        step->setValue(6);
        QCOMPARE(window_->tools().focal.contextStep, 6.0);
        window_->toolsPanel(0)->grab().save(kArtifacts + "/probes-dock.png");
        // The clip plane alone: Ctrl+drag pushes it along its normal.
        auto clipOnly = window_->tools();
        clipOnly.focal.enabled = clipOnly.context.enabled = false;
        window_->setTools(clipOnly);
        const double offset = window_->tools().clip.offset;
        QTest::mousePress(view(), Qt::LeftButton, Qt::ControlModifier, c);
        for (int i = 1; i <= 5; ++i) QTest::mouseMove(view(), c - QPoint(0, 10 * i), 10);
        QTest::mouseRelease(view(), Qt::LeftButton, Qt::ControlModifier, c - QPoint(0, 50));
        QVERIFY2(window_->tools().clip.offset > offset, "dragging up pushes the plane");
        // Out-of-range parameters are refused and the last valid tools stay.
        auto bad = window_->tools();
        bad.mimda.gamma = 2.0;
        QVERIFY_THROWS_EXCEPTION(core::Error, window_->setTools(bad));
        QCOMPARE(window_->tools().mimda.gamma, 0.5);
        // Saved with the session: a new window (as after a restart) comes back with them.
        const std::string saved = window_->tools().toJson();
        window_->close();
        {
            ui::MainWindow again(QString::fromStdString(dir_.file("db/studies.sqlite")),
                                 QString::fromStdString(dir_.file("pacs.json")));
            QCOMPARE(again.tools().toJson(), saved);
        }
        window_->show();
        QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
        window_->setTools({});
    }

    // Help > About names the version, the libraries as linked, the OpenGL renderer in use and the
    // data folders (the study database and PACS settings this window was given).
    void aboutNamesTheLibrariesAndTheFoldersInUse() {
        const QString about = window_->aboutText();
        for (const char* part : {"Qt 6.", "DCMTK 3.", "SQLite 3.", "VTK 9.", "OpenEXR ", "OpenGL: "})
            QVERIFY2(about.contains(part), qPrintable(part + QString(" missing from:\n") + about));
        QVERIFY2(about.contains(QString::fromStdString(dir_.file("db/studies.sqlite"))), qPrintable(about));
        QVERIFY2(about.contains(QString::fromStdString(dir_.file("pacs.json"))), qPrintable(about));
        QVERIFY2(!about.contains("no OpenGL context"), "the shown view has a context");
    }

    void takesScreenshotsAtTheViewsSizeOrLarger() {
        const QString png = QString::fromStdString(dir_.file("capture.png"));
        const QString exr = QString::fromStdString(dir_.file("capture.exr"));
        view()->capture(png, 800, 600);
        view()->capture(exr, 320, 240);
        const QImage shot(png);
        QCOMPARE(shot.size(), QSize(800, 600));
        QVERIFY(coverage(shot) > 0.05);
        QVERIFY(QFileInfo(exr).size() > 1000);
        QFile::remove(kArtifacts + "/capture-800x600.png");
        QFile::copy(png, kArtifacts + "/capture-800x600.png");
        saveArtifact("main-window.png");
    }

    void lightFieldDockRendersPreviewsAndDrivesTheOutputWindow() {
        auto* lf = window_->lightField();
        lf->profiles()->setCurrentText("holovizio-96");
        QVERIFY(lf->renderFrame());
        QCOMPARE(lf->frame().size(), QSize(16 * 320, 6 * 240));  // 96 projector images
        QVERIFY(coverage(lf->preview()) > 0.02);
        const QImage centre = lf->preview();
        auto sliders = lf->findChildren<QSlider*>();
        QVERIFY(sliders.size() >= 2);
        sliders.last()->setValue(-80);  // the observer walks to the left
        QVERIFY2(difference(centre, lf->preview()) > 0.5, "another observer sees another view");
        // While moving, frames use the lowered sampling rate of the thesis: fewer pixels, larger step.
        QVERIFY(lf->renderFrame(true));
        QVERIFY(lf->frame().width() < 16 * 320);
        QVERIFY(coverage(lf->frame()) > 0.01);
        lf->profiles()->setCurrentText("looking-glass-portrait");
        QVERIFY(lf->renderFrame());
        QVERIFY(coverage(lf->frame()) > 0.01);
        lf->frame().save(kArtifacts + "/quilt_qs8x6a0.75.png");
        lf->openOutputWindow();
        QTRY_VERIFY(lf->outputWindow()->isVisible());
        QCOMPARE(lf->outputWindow()->frame().size(), lf->frame().size());
        lf->outputWindow()->close();
        // The Render frame button: a job in the Jobs panel (its progress reported, done), and the
        // preview in a window of its own, where it can be seen, with the observer slider beside it.
        lf->profiles()->setCurrentText("holovizio-96");
        QSignalSpy started(window_->jobs(), &ui::JobManager::started), progressed(window_->jobs(), &ui::JobManager::progressed),
            ended(window_->jobs(), &ui::JobManager::finished);
        QTest::mouseClick(lf->findChild<QPushButton*>("lightFieldRender"), Qt::LeftButton);
        QCOMPARE(started.size(), 1);
        QCOMPARE(started[0][1].toString(), QString("Light-field frame (holovizio-96)"));
        const int job = started[0][0].toInt();
        QVERIFY2(progressed.size() >= 3, qPrintable(QString::number(progressed.size())));  // the cut, the batches, the end
        QCOMPARE(ended.last()[0].toInt(), job);
        QCOMPARE(ended.last()[1].toString(), QString("done"));
        QCOMPARE(window_->jobsPanel()->cellText(job, 2), QString("done"));
        auto* preview = lf->previewWindow();
        QVERIFY(preview);
        QTRY_VERIFY(preview->isVisible());
        QVERIFY2(preview->shown().width() >= 300, "the preview is shown large");
        QVERIFY2(coverage(preview->shown()) > 0.02, "the preview window shows the volume");
        const QImage seen = preview->shown();
        preview->observer()->setValue(70);  // its own observer slider moves the observer
        QTRY_VERIFY(difference(seen, preview->shown()) > 0.5);
        preview->grab().save(kArtifacts + "/lightfield-preview-window.png");
        preview->close();
    }

    void jobsPanelCancelsARunningBuild() {
        const std::string out = dir_.file("big.hvo");
        const int id = window_->jobs()->start("Build octree: phantom 512^3", [out](core::JobContext& job) {
            core::PhantomVoxelSource phantom({512, 512, 512}, 1, {400, 400, 400}, 10.0);
            core::OctreeBuilder(core::BuildOptions{}).build(phantom, out, job);
            return QString::fromStdString(out);
        });
        QSignalSpy finished(window_->jobs(), &ui::JobManager::finished);
        QTest::qWait(300);
        auto* cancel = window_->jobsPanel()->findChild<QPushButton*>(QStringLiteral("cancelJob%1").arg(id));
        QVERIFY(cancel);
        QTest::mouseClick(cancel, Qt::LeftButton);
        QTRY_VERIFY_WITH_TIMEOUT(!finished.isEmpty() && finished.last().at(0).toInt() == id, 60000);
        QCOMPARE(finished.last().at(1).toString(), QString("cancelled"));
        QCOMPARE(window_->jobsPanel()->cellText(id, 2), QString("cancelled"));
        QVERIFY2(!std::filesystem::exists(out), "a cancelled build leaves no output");
    }

    // A failed job's whole message is readable: in its details window (selectable), on the
    // clipboard, and in the job log that the Help menu opens.
    void failedJobsMessageIsReadableWhole() {
        const QString message = "cannot connect to 127.0.0.1:4243 (Connection refused): start the demo archive with "
                                "'holovox-cli demo', or check the node's host and port in the PACS panel; " +
                                QString(200, 'x') + " END";
        QSignalSpy finished(window_->jobs(), &ui::JobManager::finished);
        const int id = window_->jobs()->start("Retrieve for the test", [message](core::JobContext&) -> QString {
            throw core::Error(message.toStdString());
        });
        QTRY_VERIFY_WITH_TIMEOUT(!finished.isEmpty() && finished.last().at(0).toInt() == id, 10000);
        auto* panel = window_->jobsPanel();
        QVERIFY2(panel->details(id).endsWith(message), qPrintable(panel->details(id)));
        panel->copyDetails(id);
        QVERIFY(QApplication::clipboard()->text().startsWith("Retrieve for the test: failed: "));
        QVERIFY(QApplication::clipboard()->text().endsWith(" END"));
        panel->showDetails(id);
        auto* box = panel->findChild<QMessageBox*>("jobDetails");
        QVERIFY(box);
        QTRY_VERIFY(box->isVisible());
        QVERIFY(box->text().endsWith(" END"));
        box->close();
        const QString log = ui::JobsPanel::logPath();
        QVERIFY(log.endsWith("/holovox/jobs.log"));  // under the test's XDG_DATA_HOME (CI checks the real HOME is untouched)
        QFile f(log);
        QVERIFY(f.open(QIODevice::ReadOnly));
        QVERIFY(QString::fromUtf8(f.readAll()).contains("Retrieve for the test: failed: " + message));
    }

    // A damaged or wrongly typed saved session is reset with a message, never a crash.
    void damagedSavedSessionIsResetWithAMessage() {
        {
            QSettings s;
            s.setValue("tools/json", QVariantList{1, 2, 3});
            s.setValue("render/mode", QStringLiteral("not a mode"));
            s.setValue("window/state", 12345);
        }
        ui::MainWindow second(QString::fromStdString(dir_.file("db2/studies.sqlite")),
                              QString::fromStdString(dir_.file("pacs2.json")));
        QVERIFY2(second.lastError().contains("reset"), qPrintable(second.lastError()));
        QSettings s;
        QVERIFY(!s.contains("render/mode"));
        QVERIFY(!s.contains("tools/json"));
    }

    void cleanupTestCase() { close(); }
};

int main(int argc, char** argv) { return test::runGuiTests<WorkstationTest>(argc, argv); }

#include "WorkstationTest.moc"
