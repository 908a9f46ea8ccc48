// GUI tests of the measurement tools under Xvfb (Qt Test), on the CT phantom built here:
// distances, circles, angles, freehand outlines, ellipses and rectangles in the slice views,
// with their list, labels and statistics from level 0; a distance and a sphere on the 3D
// view's surface. Screenshots under <build>/test-artifacts/gui/.
#include <QApplication>
#include <QComboBox>
#include <QStatusBar>
#include <QTableWidget>
#include <QMouseEvent>
#include <QtMath>
#include <QTest>

#include <cmath>
#include <filesystem>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/RegionStatistics.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/ProcessRunner.h"
#include "tests/support/TempDir.h"
#include "tests/gui/GuiTestSupport.h"
#include "ui/JobManager.h"
#include "ui/MainWindow.h"
#include "ui/MeasurementsPanel.h"
#include "ui/SliceScroller.h"
#include "ui/SliceView.h"
#include "core/base/Error.h"
#include "ui/VolumeView.h"

using namespace hvx;

namespace {
const QString kArtifacts = test::guiArtifacts();
using test::difference;
}  // namespace

class ReadingToolsTest : public QObject, test::GuiFixture {
    Q_OBJECT

    /// The CT phantom open, seen from the front, its frame settled (the 3D picking cases).
    bool openAnteriorCt() {
        if (!window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo")))) return false;
        window_->view()->setStandardView(core::OrbitCamera::Standard::Anterior);
        settledFrame();
        return true;
    }

private slots:
    void initTestCase() {
        open();
        auto ct = test::readingCtPhantom();
        core::JobContext job;
        core::OctreeBuilder(core::BuildOptions{}).build(ct, dir_.file("w-ct.hvo"), job);
    }

    // Shift-drag measures a distance in mm (the pixel size being the volume's extent over the
    // view's shorter side), Ctrl-drag a circle's statistics, computed from level 0 for the
    // disc one slice thick that was drawn; Esc clears both.
    void sliceViewMeasuresADistanceAndACircle() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        QVERIFY(QTest::qWaitForWindowExposed(axial));
        const QPoint a(axial->width() / 2 - 40, axial->height() / 2), b(axial->width() / 2 + 20, axial->height() / 2);
        QTest::mousePress(axial, Qt::LeftButton, Qt::ShiftModifier, a);
        QMouseEvent drag(QEvent::MouseMove, QPointF(b), axial->mapToGlobal(QPointF(b)), Qt::NoButton, Qt::LeftButton,
                         Qt::ShiftModifier);
        QApplication::sendEvent(axial, &drag);
        QTest::mouseRelease(axial, Qt::LeftButton, Qt::ShiftModifier, b);
        QVERIFY(axial->rulerMm().has_value());
        const double pixelMm = 300.0 / std::min(axial->width(), axial->height());  // the phantom spans 300 mm
        QVERIFY2(std::abs(*axial->rulerMm() - 60 * pixelMm) < 1e-6 * 60 * pixelMm,
                 qPrintable(QString("%1 mm for 60 px of %2 mm").arg(*axial->rulerMm()).arg(pixelMm)));
        // A circle of 25 px around the view's centre.
        const QPoint c(axial->width() / 2, axial->height() / 2), rim = c + QPoint(25, 0);
        QTest::mousePress(axial, Qt::LeftButton, Qt::ControlModifier, c);
        QMouseEvent grow(QEvent::MouseMove, QPointF(rim), axial->mapToGlobal(QPointF(rim)), Qt::NoButton, Qt::LeftButton,
                         Qt::ControlModifier);
        QApplication::sendEvent(axial, &grow);
        QTest::mouseRelease(axial, Qt::LeftButton, Qt::ControlModifier, rim);
        QVERIFY(axial->roiStatistics().has_value());
        const auto& roi = *axial->roi();
        QVERIFY2(std::abs(roi.radius - 25 * pixelMm) < 1e-6 * 25 * pixelMm, qPrintable(QString::number(roi.radius)));
        QCOMPARE(roi.normal, glm::dvec3(0, 0, 1));
        const auto reader = core::OctreeReader::open(dir_.file("w-ct.hvo"));
        const auto direct = core::RegionStatistics::compute(*reader, roi);
        QCOMPARE(axial->roiStatistics()->voxels, direct.voxels);
        QCOMPARE(axial->roiStatistics()->mean, direct.mean);
        QVERIFY(direct.voxels > 10);
        QCOMPARE(axial->roiStatistics()->units, std::string("HU"));
        QVERIFY2(axial->roiText().startsWith("mean ") && !axial->roiText().contains("slab"), qPrintable(axial->roiText()));
        axial->setSlab(20, core::SlabMode::Mip);  // the statistics stay the thin slice's, and say so
        QVERIFY2(axial->roiText().contains("not the 20.0 mm slab shown"), qPrintable(axial->roiText()));
        axial->setSlab(0, core::SlabMode::Mip);
        settledFrame();
        saveArtifact("slice-measurements.png");
        // Both went to the measurement list: its table, CSV and JSON exports (read back by
        // Python's csv and json modules), Del removes one, and the list comes back with the volume.
        auto* panel = window_->measurements();
        QCOMPARE(panel->list().items().size(), std::size_t(2));
        QCOMPARE(panel->table()->rowCount(), 2);
        QCOMPARE(panel->table()->item(0, 1)->text(), QString("distance"));
        QVERIFY2(panel->table()->item(0, 3)->text().contains(QString::number(*axial->rulerMm(), 'f', 1)),
                 qPrintable(panel->table()->item(0, 3)->text()));
        QVERIFY2(panel->table()->item(1, 3)->text().contains("HU"), qPrintable(panel->table()->item(1, 3)->text()));
        const QString csv = QString::fromStdString(dir_.file("m.csv")), json = QString::fromStdString(dir_.file("m.json"));
        QVERIFY(panel->exportTo(csv).isEmpty());
        QVERIFY(panel->exportTo(json).isEmpty());
        const auto py = test::runCommand("/usr/bin/python3 -c \"import csv,json; r=list(csv.DictReader(open('" +
                                         csv.toStdString() + "'))); j=json.load(open('" + json.toStdString() +
                                         "')); print(len(r), r[1]['voxels'], r[1]['units'], len(j['measurements']), "
                                         "j['measurements'][0]['kind'])\"");
        QCOMPARE(QString::fromStdString(py.output).trimmed(),
                 QString("2 %1 HU 2 distance").arg(qulonglong(axial->roiStatistics()->voxels)));
        QVERIFY2(panel->exportTo("/nonexistent-dir/m.csv").contains("nonexistent"), "a folder that is not there is named");
        panel->table()->clearSelection();
        panel->table()->selectRow(0);
        panel->table()->setFocus();
        QTest::keyClick(panel->table(), Qt::Key_Delete);
        QCOMPARE(panel->list().items().size(), std::size_t(1));
        QCOMPARE(panel->list().items()[0].label, std::string("M2"));
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));  // again: the list is kept
        QCOMPARE(panel->list().items().size(), std::size_t(1));
        QCOMPARE(panel->list().items()[0].label, std::string("M2"));
        axial->setFocus();
        QTest::keyClick(axial, Qt::Key_Escape);
        QVERIFY(!axial->rulerMm().has_value());
        QVERIFY(!axial->roi().has_value());
    }

    // A, then three clicks, measures an angle (a right angle drawn on the screen's axes is
    // 90.0 degrees); every measurement of the list is drawn with its label on its slice, and
    // only there; Del on the view removes the newest one on the slice.
    void sliceViewMeasuresAnAngleAndDrawsTheList() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        auto* panel = window_->measurements();
        const std::size_t before = panel->list().items().size();
        const QPoint vertex(axial->width() / 2 + 10, axial->height() / 2 + 30);
        const QPoint end1 = vertex + QPoint(-50, 0), end2 = vertex + QPoint(0, -40);
        axial->setFocus();
        QTest::keyClick(axial, Qt::Key_A);
        QTest::mouseClick(axial, Qt::LeftButton, Qt::NoModifier, end1);
        QTest::mouseClick(axial, Qt::LeftButton, Qt::NoModifier, vertex);
        QCOMPARE(axial->anglePoints().size(), std::size_t(3));  // two placed, one following the mouse
        QTest::mouseClick(axial, Qt::LeftButton, Qt::NoModifier, end2);
        QVERIFY(axial->anglePoints().empty());
        QCOMPARE(panel->list().items().size(), before + 1);
        const auto& angle = panel->list().items().back();
        QCOMPARE(angle.kind, core::Measurement::Kind::Angle);
        QVERIFY2(std::abs(angle.angleDegrees() - 90.0) < 1e-9, qPrintable(QString::number(angle.angleDegrees())));
        const int row = panel->table()->rowCount() - 1;
        QCOMPARE(panel->table()->item(row, 1)->text(), QString("angle"));
        QCOMPARE(panel->table()->item(row, 3)->text(), QString("90.0\u00b0"));
        // Drawn on this slice: the arms' middles are the measurement colour; one slice up, not.
        const auto green = [](const QImage& img, QPoint at) {
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const QColor c = img.pixelColor(at + QPoint(dx, dy));
                    if (c.green() > 200 && c.red() < 170 && c.blue() < 190) return true;
                }
            return false;
        };
        QImage shot = axial->grab().toImage();
        QVERIFY(green(shot, (end1 + vertex) / 2));
        QVERIFY(green(shot, (end2 + vertex) / 2));
        shot.save(kArtifacts + "/slice-angle-and-list.png");
        QTest::keyClick(axial, Qt::Key_Up);
        QVERIFY2(!green(axial->grab().toImage(), (end1 + vertex) / 2), "an angle drawn on a slice it is not on");
        QTest::keyClick(axial, Qt::Key_Down);
        QTest::keyClick(axial, Qt::Key_Delete);  // the newest on this slice: the angle
        QCOMPARE(panel->list().items().size(), before);
        QVERIFY(std::none_of(panel->list().items().begin(), panel->list().items().end(),
                             [](const core::Measurement& m) { return m.kind == core::Measurement::Kind::Angle; }));
    }

    // D, then two clicks on the 3D view, measures a distance between two points of the rendered
    // surface (the ray caster's depth): each end projects back under its click and lies inside
    // the volume; the list says "3D"; a click on nothing picks nothing and says so.
    void threeDViewMeasuresADistanceOnTheSurface() {
        QVERIFY(openAnteriorCt());
        auto* v = window_->view();
        auto* panel = window_->measurements();
        const std::size_t before = panel->list().items().size();
        const QPoint a(v->width() / 2, v->height() / 2), b(v->width() / 2, v->height() / 2 - 60);
        QVERIFY2(v->surfaceAt(a).has_value() && v->surfaceAt(b).has_value(), "the spine is not under the view's centre");
        v->setFocus();
        QTest::keyClick(v, Qt::Key_D);
        QVERIFY(v->measuringDistance());
        QTest::mouseClick(v, Qt::LeftButton, Qt::NoModifier, QPoint(3, 3));  // black corner: nothing there
        QVERIFY(v->measuringDistance());
        QVERIFY2(window_->statusBar()->currentMessage().contains("nothing under the cursor"),
                 qPrintable(window_->statusBar()->currentMessage()));
        QTest::mouseClick(v, Qt::LeftButton, Qt::NoModifier, a);
        QTest::mouseClick(v, Qt::LeftButton, Qt::NoModifier, b);
        QVERIFY(!v->measuringDistance());
        QCOMPARE(panel->list().items().size(), before + 1);
        const auto& m = panel->list().items().back();
        QCOMPARE(m.view, std::string("3D"));
        const auto reader = core::OctreeReader::open(dir_.file("w-ct.hvo"));
        const glm::dmat4 toIndex = glm::inverse(reader->geometry().indexToPatient());
        for (const auto& [end, click] : {std::pair{m.a, a}, std::pair{m.b, b}}) {
            QPointF at;
            double depth = 0;
            QVERIFY(v->project(end, at, depth));
            QVERIFY2(std::hypot(at.x() - click.x(), at.y() - click.y()) < 1.5,
                     qPrintable(QString("(%1, %2) for a click at (%3, %4)").arg(at.x()).arg(at.y()).arg(click.x()).arg(click.y())));
            const glm::dvec3 i(toIndex * glm::dvec4(end, 1.0));
            for (int k = 0; k < 3; ++k)
                QVERIFY(i[k] >= -0.5 && i[k] <= reader->geometry().dims[std::size_t(k)] - 0.5);
        }
        QVERIFY(m.lengthMm() > 0.0);
        saveArtifact("volume-distance.png");
        QTest::keyClick(v, Qt::Key_D);
        QTest::keyClick(v, Qt::Key_Escape);
        QVERIFY(!v->measuringDistance());
    }

    // B, then two clicks on the rendered surface: a sphere about the first point through the
    // second, its statistics from level 0 (as computing that sphere gives), listed as a sphere
    // and drawn as its outline; a click on nothing is refused with a sentence.
    void threeDViewMeasuresASphere() {
        QVERIFY(openAnteriorCt());
        auto* v = window_->view();
        auto* panel = window_->measurements();
        const std::size_t before = panel->list().items().size();
        const QPoint a(v->width() / 2, v->height() / 2), b(v->width() / 2, v->height() / 2 - 30);  // on the spine
        const auto centre = v->surfaceAt(a), rim = v->surfaceAt(b);
        QVERIFY2(centre && rim, "the spine is not under the view's centre");
        v->setFocus();
        QTest::keyClick(v, Qt::Key_B);
        QVERIFY(v->measuringSphere());
        QTest::mouseClick(v, Qt::LeftButton, Qt::NoModifier, QPoint(3, 3));
        QVERIFY(v->measuringSphere());
        QVERIFY2(window_->statusBar()->currentMessage().contains("Sphere: nothing under the cursor"),
                 qPrintable(window_->statusBar()->currentMessage()));
        QTest::mouseClick(v, Qt::LeftButton, Qt::NoModifier, a);
        QTest::mouseClick(v, Qt::LeftButton, Qt::NoModifier, b);
        QVERIFY(!v->measuringSphere());
        QCOMPARE(panel->list().items().size(), before + 1);
        const auto m = panel->list().items().back();
        QVERIFY(m.region && m.stats);
        QCOMPARE(m.region->kind, core::MeasureRegion::Kind::Sphere);
        QVERIFY(glm::length(m.region->centre - *centre) < 1e-9);
        QVERIFY(std::abs(m.region->radius - glm::length(*rim - *centre)) < 1e-9);
        const auto reader = core::OctreeReader::open(dir_.file("w-ct.hvo"));
        const auto direct = core::RegionStatistics::compute(*reader, *m.region);
        QCOMPARE(m.stats->voxels, direct.voxels);
        QCOMPARE(m.stats->mean, direct.mean);
        QVERIFY(direct.voxels > 10);
        QCOMPARE(panel->table()->item(panel->table()->rowCount() - 1, 1)->text(), QString("sphere"));
        QVERIFY2(window_->statusBar()->currentMessage().contains(QString("%1 voxels").arg(direct.voxels)),
                 qPrintable(window_->statusBar()->currentMessage()));
        // Its outline: a circle through the rim point as seen, in the measurement colour.
        QPointF c, r;
        double depth = 0;
        QVERIFY(v->project(m.region->centre, c, depth));
        QVERIFY(v->project(m.region->centre + m.region->radius * v->camera().right(), r, depth));
        const auto greenNear = [](const QImage& shot, QPointF at) {
            bool drawn = false;
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) {
                    const QColor px = shot.pixelColor(at.toPoint() + QPoint(dx, dy));
                    drawn = drawn || (px.green() > 200 && px.red() < 170 && px.blue() < 190);
                }
            return drawn;
        };
        QVERIFY2(greenNear(v->grab().toImage(), r), "no sphere outline at its rim");
        saveArtifact("volume-sphere.png");
        // In a slice view: the circle the slice cuts from it, of the sphere's radius through its
        // centre, smaller off it, none beyond it.
        auto* axial = window_->slice(0);
        const glm::dvec3 centre3 = m.region->centre;
        const double radius = m.region->radius;
        axial->setPoint(centre3);
        QVERIFY2(greenNear(axial->grab().toImage(), axial->widgetAt(centre3 + glm::dvec3(radius, 0, 0))),
                 "no circle where the axial slice through the centre cuts the sphere");
        axial->grab().save(kArtifacts + "/slice-sphere-cut.png");
        axial->setPoint(centre3 + glm::dvec3(0, 0, 0.6 * radius));  // cut radius 0.8 r
        QVERIFY(greenNear(axial->grab().toImage(), axial->widgetAt(centre3 + glm::dvec3(0.8 * radius, 0, 0))));
        QVERIFY(!greenNear(axial->grab().toImage(), axial->widgetAt(centre3 + glm::dvec3(radius, 0, 0))));
        axial->setPoint(centre3 + glm::dvec3(0, 0, radius * 1.2));
        for (const double f : {0.5, 0.8, 1.0})
            QVERIFY2(!greenNear(axial->grab().toImage(), axial->widgetAt(centre3 + glm::dvec3(f * radius, 0, 0))),
                     "a circle on a slice beyond the sphere");
    }

    // Ctrl+Shift-drag draws a freehand outline: its statistics come from level 0 for the slice
    // it was drawn on (the same as computing the region it stored), its area is the drawn one's
    // within the voxels along its edge, and it is listed as an outline and drawn with its label.
    void sliceViewMeasuresAFreehandOutline() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        auto* panel = window_->measurements();
        const std::size_t before = panel->list().items().size();
        const QPoint c(axial->width() / 2, axial->height() / 2);
        const QList<QPoint> corners{c + QPoint(-30, -20), c + QPoint(30, -20), c + QPoint(30, 25), c + QPoint(-30, 25)};
        QTest::mousePress(axial, Qt::LeftButton, Qt::ControlModifier | Qt::ShiftModifier, corners[0]);
        for (int i = 1; i <= 4; ++i) {
            const QPoint at = corners[i % 4];
            QMouseEvent move(QEvent::MouseMove, QPointF(at), axial->mapToGlobal(QPointF(at)), Qt::NoButton, Qt::LeftButton,
                             Qt::ControlModifier | Qt::ShiftModifier);
            QApplication::sendEvent(axial, &move);
        }
        QTest::mouseRelease(axial, Qt::LeftButton, Qt::ControlModifier | Qt::ShiftModifier, corners[0]);
        QCOMPARE(panel->list().items().size(), before + 1);
        const auto& m = panel->list().items().back();
        QVERIFY(m.region && m.stats);
        QCOMPARE(m.region->kind, core::MeasureRegion::Kind::Polygon);
        const int row = panel->table()->rowCount() - 1;
        QCOMPARE(panel->table()->item(row, 1)->text(), QString("outline"));
        const auto reader = core::OctreeReader::open(dir_.file("w-ct.hvo"));
        const auto direct = core::RegionStatistics::compute(*reader, *m.region);
        QCOMPARE(m.stats->voxels, direct.voxels);
        QCOMPARE(m.stats->mean, direct.mean);
        const double pixelMm = 300.0 / std::min(axial->width(), axial->height());
        const double drawn = 60 * pixelMm * 45 * pixelMm;  // mm^2
        const auto& g = reader->geometry();
        const double edgeVoxels = 2 * (60 + 45) * pixelMm / g.spacing.x;  // voxels along the outline
        QVERIFY2(std::abs(m.stats->areaMm2 - drawn) <= edgeVoxels * g.spacing.x * g.spacing.y,
                 qPrintable(QString("%1 mm2 for %2 drawn").arg(m.stats->areaMm2).arg(drawn)));
        axial->grab().save(kArtifacts + "/slice-outline.png");
    }

    // The region shape chosen in the Measurements dock: Ctrl-drag draws an ellipse or a rectangle
    // corner to corner, measured from level 0 as drawn; dragging a handle edits a measurement in
    // place (same label, measured again), and one made degenerate is refused with a sentence.
    void sliceViewDrawsEllipsesAndRectanglesAndEditsThemByHandles() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        auto* panel = window_->measurements();
        const auto reader = core::OctreeReader::open(dir_.file("w-ct.hvo"));
        const double pixelMm = 300.0 / std::min(axial->width(), axial->height());
        const QPoint c(axial->width() / 2, axial->height() / 2);
        const auto expectMeasured = [&](const core::Measurement& m) {
            QVERIFY(m.region && m.stats);
            const auto direct = core::RegionStatistics::compute(*reader, *m.region);
            QCOMPARE(m.stats->voxels, direct.voxels);
            QCOMPARE(m.stats->mean, direct.mean);
            QVERIFY(direct.voxels > 10);
        };
        panel->shapeChooser()->setCurrentIndex(1);  // ellipse
        std::size_t before = panel->list().items().size();
        test::leftDrag(axial, c - QPoint(30, 15), c + QPoint(30, 15), Qt::ControlModifier);
        QCOMPARE(panel->list().items().size(), before + 1);
        const std::string ellipseLabel = panel->list().items().back().label;
        {
            const auto& m = panel->list().items().back();
            QCOMPARE(m.region->kind, core::MeasureRegion::Kind::Ellipse);
            QVERIFY2(std::abs(m.region->radius - 30 * pixelMm) < 1e-6 && std::abs(m.region->radius2 - 15 * pixelMm) < 1e-6,
                     qPrintable(QString("%1 x %2 mm").arg(m.region->radius).arg(m.region->radius2)));
            expectMeasured(m);
            QCOMPARE(panel->table()->item(panel->table()->rowCount() - 1, 1)->text(), QString("ellipse"));
        }
        panel->shapeChooser()->setCurrentIndex(2);  // rectangle, below the ellipse
        const QPoint r0 = c + QPoint(-40, 30), r1 = c + QPoint(20, 60);
        test::leftDrag(axial, r0, r1, Qt::ControlModifier);
        QCOMPARE(panel->list().items().size(), before + 2);
        const std::string rectLabel = panel->list().items().back().label;
        {
            const auto& m = panel->list().items().back();
            QCOMPARE(m.region->kind, core::MeasureRegion::Kind::Rectangle);
            expectMeasured(m);
            QVERIFY2(std::abs(m.stats->areaMm2 - 60 * 30 * pixelMm * pixelMm) < 2 * (60 + 30) * pixelMm * 7.0,
                     qPrintable(QString::number(m.stats->areaMm2)));  // within a voxel (7 mm here) of the edges
        }
        panel->shapeChooser()->setCurrentIndex(0);
        settledFrame();
        axial->grab().save(kArtifacts + "/slice-ellipse-rectangle.png");
        // The ellipse's axis end (its handle at the right of the centre) dragged out by 15 px.
        const auto handles = axial->measurementHandles();
        const QPoint axisEnd = c + QPoint(30, 0);
        QVERIFY(std::any_of(handles.begin(), handles.end(),
                            [&](const QPointF& h) { return std::hypot(h.x() - axisEnd.x(), h.y() - axisEnd.y()) < 1.0; }));
        before = panel->list().items().size();
        const glm::dvec3 cursor = axial->point();
        test::leftDrag(axial, axisEnd, axisEnd + QPoint(15, 0));
        QCOMPARE(axial->point(), cursor);  // the drag was the handle's, not the cursor's
        QCOMPARE(panel->list().items().size(), before);
        const auto find = [&](const std::string& label) {
            return *std::find_if(panel->list().items().begin(), panel->list().items().end(),
                                 [&](const core::Measurement& m) { return m.label == label; });
        };
        {
            const auto m = find(ellipseLabel);
            QVERIFY2(std::abs(m.region->radius - 45 * pixelMm) < 1e-6, qPrintable(QString::number(m.region->radius)));
            QVERIFY(std::abs(m.region->radius2 - 15 * pixelMm) < 1e-6);
            expectMeasured(m);
        }
        // The rectangle moved by its centre handle, 10 px right: same size, measured again.
        const auto oldRect = find(rectLabel);
        const QPoint centre = (r0 + r1) / 2;
        test::leftDrag(axial, centre, centre + QPoint(10, 0));
        {
            const auto m = find(rectLabel);
            QVERIFY(glm::length(m.region->centre - oldRect.region->centre - glm::dvec3(10 * pixelMm, 0, 0)) < 1e-6);
            expectMeasured(m);
        }
        // A corner dragged onto its neighbour's side leaves no area: refused, the rectangle kept.
        const auto kept = find(rectLabel);
        const QPoint corner = axial->widgetAt(kept.region->outline[2]).toPoint();
        const QPoint flat(corner.x(), axial->widgetAt(kept.region->outline[0]).toPoint().y());
        test::leftDrag(axial, corner, flat);
        QCOMPARE(find(rectLabel).region->outline, kept.region->outline);
        QVERIFY2(axial->roiError().contains("no area"), qPrintable(axial->roiError()));
        axial->grab().save(kArtifacts + "/slice-edited-by-handles.png");
        // Saved with the session: a new window (as after a restart) opening the volume has the
        // list as edited, shapes and statistics included.
        const std::string saved = panel->list().toJson({});
        ui::MainWindow again(QString::fromStdString(dir_.file("db/studies.sqlite")), QString::fromStdString(dir_.file("pacs.json")));
        QVERIFY(again.openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        QCOMPARE(again.measurements()->list().toJson({}), saved);
    }

    void cleanupTestCase() { close(); }
};

int main(int argc, char** argv) { return test::runGuiTests<ReadingToolsTest>(argc, argv); }

#include "ReadingToolsTest.moc"
