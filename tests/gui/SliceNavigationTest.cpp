// GUI tests of reading a volume slice by slice under Xvfb (Qt Test), on volumes built here:
// each volume's window and presets by key; the slider and cine, slab, stepping and level
// readout; crosshair reformat and the slice along the 3D view; and left never shown as right.
// Screenshots under <build>/test-artifacts/gui/.
#include <QApplication>
#include <QComboBox>
#include <QSlider>
#include <QStatusBar>
#include <QMouseEvent>
#include <QSet>
#include <QtMath>
#include <QTest>
#include <QWheelEvent>

#include <cmath>
#include <filesystem>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/RegionStatistics.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/support/MemoryVoxelSource.h"
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

class SliceNavigationTest : public QObject, test::GuiFixture {
    Q_OBJECT

private slots:
    void initTestCase() { open(); }

    // A CT opened after an MR gets its own window (not the MR's), the number keys pick the CT
    // presets in all three views, a window chosen for a volume comes back when it is opened
    // again, and the pixels follow.
    void eachVolumeOpensWithItsOwnWindowAndPresetsByKey() {
        core::JobContext job;
        auto ct = test::readingCtPhantom();
        core::OctreeBuilder(core::BuildOptions{}).build(ct, dir_.file("w-ct.hvo"), job);
        core::VolumeGeometry mrg = ct.geometry();
        mrg.modality = "MR";
        mrg.scalarType = core::ScalarType::UInt16;
        mrg.rescaleSlope = 1;
        mrg.rescaleIntercept = 0;
        test::DenseVolume mv;
        mv.dims = mrg.dims;
        for (std::size_t i = 0; i < std::size_t(48 * 48 * 48); ++i) mv.values.push_back(double((i * 37) % 1000));
        test::MemoryVoxelSource mr(mrg, mv);
        core::OctreeBuilder(core::BuildOptions{}).build(mr, dir_.file("w-mr.hvo"), job);
        auto* axial = window_->slice(0);
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-mr.hvo"))));
        QVERIFY(window_->jobs()->waitIdle(60000));  // the histogram's percentile window
        QVERIFY2(axial->windowWidth() < 1000.0 && axial->windowWidth() > 900.0, qPrintable(QString::number(axial->windowWidth())));
        // The user narrows the MR's window with a right drag: remembered for this volume.
        QTest::mousePress(axial, Qt::RightButton, {}, QPoint(40, 40));
        QMouseEvent drag(QEvent::MouseMove, QPointF(10, 40), axial->mapToGlobal(QPointF(10, 40)), Qt::NoButton,
                         Qt::RightButton, Qt::NoModifier);
        QApplication::sendEvent(axial, &drag);
        QTest::mouseRelease(axial, Qt::RightButton, {}, QPoint(10, 40));
        const double mrWidth = axial->windowWidth(), mrCentre = axial->windowCentre();
        QVERIFY(mrWidth < 900.0);
        QCOMPARE(window_->slice(1)->windowWidth(), mrWidth);  // one window for the three views

        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        QCOMPARE(axial->windowCentre(), 40.0);
        QCOMPARE(axial->windowWidth(), 400.0);
        const QImage soft = axial->image();
        axial->setFocus();
        QTest::keyClick(axial, Qt::Key_5);  // CT presets: 1 brain ... 5 lung
        QCOMPARE(axial->windowName(), QString("lung"));
        QCOMPARE(window_->slice(2)->windowCentre(), -600.0);
        QVERIFY2(difference(soft, axial->image()) > 5.0, "the lung window shows the same pixels as W 400 / L 40");
        saveArtifact("slices-lung-window.png");

        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-mr.hvo"))));
        QCOMPARE(axial->windowWidth(), mrWidth);
        QCOMPARE(axial->windowCentre(), mrCentre);
        QVERIFY(window_->jobs()->waitIdle(60000));
        QCOMPARE(axial->windowWidth(), mrWidth);  // the percentile window does not override a choice
    }

    // The slider under each view spans its slices and scrolls the view; keys and clicks in
    // another view move it; cine plays through the slices at the chosen rate and loops.
    void sliceScrollerFollowsAndPlays() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        auto* bar = window_->scroller(0);
        QCOMPARE(bar->slider()->maximum(), 47);  // w-ct.hvo: 48 slices
        QCOMPARE(bar->slider()->value(), axial->sliceIndex());
        bar->slider()->setValue(10);
        QCOMPARE(axial->sliceIndex(), 10);
        QVERIFY2(axial->slicePosition().startsWith("slice 11/48"), qPrintable(axial->slicePosition()));
        axial->setFocus();
        QTest::keyClick(axial, Qt::Key_Up);
        QCOMPARE(bar->slider()->value(), axial->sliceIndex());
        // A click in the coronal view moves the axial slice: its slider follows. The coronal
        // view's top is superior, so a click in its upper quarter takes the axial plane up, to
        // the slice nearest the clicked height by the volume's own index-to-patient transform.
        auto* coronal = window_->slice(1);
        QCOMPARE(coronal->edgeLabels().at(2), QString("S"));
        const int axialBefore = axial->sliceIndex();
        const double heightBefore = axial->point().z;
        const QPoint click(coronal->width() / 2, coronal->height() / 4);
        QTest::mouseClick(coronal, Qt::LeftButton, Qt::NoModifier, click);
        const glm::dvec3 clicked = coronal->point();
        QCOMPARE(axial->point(), clicked);  // the views share the point
        QCOMPARE(window_->slice(2)->point(), clicked);
        QVERIFY2(clicked.z > heightBefore + 5.0, qPrintable(QString("%1 -> %2 mm").arg(heightBefore).arg(clicked.z)));
        QVERIFY(std::abs(coronal->widgetAt(clicked).y() - click.y()) < 1.0);
        const auto geometry = core::OctreeReader::open(dir_.file("w-ct.hvo"))->geometry();
        const glm::dvec4 ijk = glm::inverse(geometry.indexToPatient()) * glm::dvec4(clicked, 1.0);
        QCOMPARE(axial->sliceIndex(), int(std::lround(ijk.z)));
        QVERIFY(axial->sliceIndex() > axialBefore);
        QCOMPARE(bar->slider()->value(), axial->sliceIndex());
        bar->slider()->setValue(45);
        bar->setRate(20);
        bar->setPlaying(true);
        QTRY_VERIFY_WITH_TIMEOUT(axial->sliceIndex() < 45, 5000);  // past the last slice, back to the first
        QTRY_VERIFY_WITH_TIMEOUT(axial->sliceIndex() >= 3, 5000);
        bar->setPlaying(false);
        const int stopped = axial->sliceIndex();
        QTest::qWait(300);
        QCOMPARE(axial->sliceIndex(), stopped);
        QCOMPARE(bar->slider()->value(), stopped);
        window_->grab().save(kArtifacts + "/slices-with-scrollers.png");
        coronal->grab().save(kArtifacts + "/slice-coronal.png");
    }

    // A native plane shows the voxel layer nearest the point, up to half a slice from it: the
    // crosshair lines of the other views are drawn where that layer is, not where the mouse
    // was, and the slice readout gives the layer's position (w-ct.hvo: 5 mm voxels).
    void crosshairLinesLieOnTheLayersShown() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        auto* coronal = window_->slice(1);
        auto* sagittal = window_->slice(2);
        QVERIFY(QTest::qWaitForWindowExposed(coronal));
        const auto geometry = core::OctreeReader::open(dir_.file("w-ct.hvo"))->geometry();
        const glm::dmat4 toIndex = glm::inverse(geometry.indexToPatient());
        auto fraction = [&](const glm::dvec3& p) {  // signed distance from the nearest axial layer, in slices
            const double k = (toIndex * glm::dvec4(p, 1.0)).z;
            return k - std::round(k);
        };
        // A row of the coronal view about 0.4 of a slice off a layer.
        int row = coronal->height() / 4;
        for (int y = coronal->height() / 4; y < coronal->height() / 2; ++y)
            if (std::abs(std::abs(fraction(coronal->patientAt(QPointF(coronal->width() / 2, y)))) - 0.4) <
                std::abs(std::abs(fraction(coronal->patientAt(QPointF(coronal->width() / 2, row)))) - 0.4))
                row = y;
        const QPoint click(coronal->width() / 2, row);
        QTest::mouseClick(coronal, Qt::LeftButton, Qt::NoModifier, click);
        const glm::dvec3 clicked = coronal->point();
        QVERIFY2(std::abs(fraction(clicked)) > 0.3, qPrintable(QString::number(fraction(clicked))));
        const glm::dvec3 layer = axial->plane().centre;
        QVERIFY2(std::abs(fraction(layer)) < 1e-6, "the axial view shows a voxel layer");
        QVERIFY(std::abs(layer.z - clicked.z) > 0.3 * geometry.spacing[2]);
        QVERIFY2(axial->slicePosition().endsWith(QString::number(layer.z, 'f', 1) + " mm"), qPrintable(axial->slicePosition()));
        // The coronal and sagittal views draw the axial plane's line on that layer (their second
        // and first cross planes), a few pixels from the click; each view's own cursor lines
        // still cross at the point where the views are native to it.
        for (auto [view, line] : {std::pair{coronal, 1}, std::pair{sagittal, 0}}) {
            const auto anchors = view->crosshairAnchors();
            QCOMPARE(anchors.size(), std::size_t(2));
            const double want = view->widgetAt(layer).y();
            QVERIFY2(std::abs(anchors[std::size_t(line)].y() - want) < 0.01,
                     qPrintable(QString("view %1: line at %2, layer at %3").arg(line)
                                    .arg(anchors[std::size_t(line)].y()).arg(want)));
            QVERIFY(std::abs(anchors[std::size_t(line)].y() - view->widgetAt(clicked).y()) > 1.0);
            QVERIFY2(std::abs(view->crosshairCentre().y() - want) < 0.01, "the lines cross on the layer");
        }
        saveArtifact("slices-crosshair-on-layers.png");
    }

    // An axial view collapsed to a pixel's width shows nothing, but when its slice moves the
    // coronal view's line for it still follows (it had stayed where the slice had been).
    void collapsedViewsPlaneStillDrawnInTheOthers() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        auto* coronal = window_->slice(1);
        QVERIFY(QTest::qWaitForWindowExposed(coronal));
        const glm::dvec3 start = axial->plane().centre;
        axial->setFixedWidth(1);
        QTRY_VERIFY(axial->width() < 2);
        const auto geometry = core::OctreeReader::open(dir_.file("w-ct.hvo"))->geometry();
        const glm::dvec3 moved = start + glm::dvec3(0.0, 0.0, 6.0 * geometry.spacing[2]);
        axial->setPoint(moved);
        const glm::dvec3 layer = axial->plane().centre;
        QVERIFY(std::abs(layer.z - start.z) > 5.0 * geometry.spacing[2]);
        const auto anchors = coronal->crosshairAnchors();
        QCOMPARE(anchors.size(), std::size_t(2));
        QVERIFY2(std::abs(anchors[1].y() - coronal->widgetAt(layer).y()) < 0.01,
                 qPrintable(QString("line at %1, slice at %2").arg(anchors[1].y()).arg(coronal->widgetAt(layer).y())));
        axial->setMinimumWidth(0);
        axial->setMaximumWidth(QWIDGETSIZE_MAX);
        QTRY_VERIFY(axial->width() > 100);
    }

    // Dragging a crosshair handle in the axial view turns the coronal and sagittal planes about
    // the axial normal: they stay perpendicular to it and to each other, turned by the angle the
    // mouse went round the cursor; the axial crosshair follows the mouse; their letters stay
    // right; O puts all three back on the acquisition axes.
    void crosshairHandleRotatesTheOtherPlanes() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        auto* coronal = window_->slice(1);
        auto* sagittal = window_->slice(2);
        QVERIFY(QTest::qWaitForWindowExposed(axial));
        const auto handles = axial->rotationHandles();
        QCOMPARE(handles.size(), std::size_t(4));
        // The handle to the right of the cursor, on the horizontal line (the coronal plane's).
        const QPointF c = axial->crosshairCentre();  // within half a slice of the cursor: on the layers shown
        const auto right = std::max_element(handles.begin(), handles.end(),
                                            [](const QPointF& a, const QPointF& b) { return a.x() < b.x(); });
        const QPoint press = right->toPoint();
        const double r = std::hypot(right->x() - c.x(), right->y() - c.y());
        QTest::mousePress(axial, Qt::LeftButton, Qt::NoModifier, press);
        QPoint last = press;
        for (int degrees = 10; degrees <= 30; degrees += 10) {  // counterclockwise on the screen
            last = QPointF(c.x() + r * std::cos(qDegreesToRadians(double(degrees))),
                           c.y() - r * std::sin(qDegreesToRadians(double(degrees)))).toPoint();
            QMouseEvent move(QEvent::MouseMove, QPointF(last), axial->mapToGlobal(QPointF(last)), Qt::NoButton,
                             Qt::LeftButton, Qt::NoModifier);
            QApplication::sendEvent(axial, &move);
        }
        QTest::mouseRelease(axial, Qt::LeftButton, Qt::NoModifier, last);
        const double turned = qRadiansToDegrees(std::atan2(-(last.y() - c.y()), last.x() - c.x()) -
                                                std::atan2(-(press.y() - c.y()), press.x() - c.x()));
        QVERIFY2(std::abs(turned - 30.0) < 2.0, qPrintable(QString::number(turned)));
        const glm::dvec3 na = axial->normal(), nc = coronal->normal(), ns = sagittal->normal();
        QVERIFY(std::abs(glm::dot(na, nc)) < 1e-9 && std::abs(glm::dot(na, ns)) < 1e-9 && std::abs(glm::dot(nc, ns)) < 1e-9);
        QVERIFY2(std::abs(coronal->tiltDegrees() - std::abs(turned)) < 1e-6,
                 qPrintable(QString("%1 for %2").arg(coronal->tiltDegrees()).arg(turned)));
        QVERIFY(std::abs(sagittal->tiltDegrees() - std::abs(turned)) < 1e-6);
        QCOMPARE(axial->tiltDegrees(), 0.0);
        // The axial crosshair now runs through where the mouse let go (the handle turned by as much
        // as the mouse did about the cursor, from where it was grabbed: the press was rounded to
        // a whole pixel off the handle's centre); the turned planes are no longer native, so
        // they pass through the cursor itself.
        const double grabbed = std::atan2(right->y() - c.y(), right->x() - c.x()) - std::atan2(press.y() - c.y(), press.x() - c.x());
        const double mouse = std::atan2(last.y() - c.y(), last.x() - c.x()) + grabbed;
        bool follows = false;
        for (const QPointF& h : axial->rotationHandles())
            follows |= std::abs(std::remainder(std::atan2(h.y() - c.y(), h.x() - c.x()) - mouse, 2 * M_PI)) < 1e-6;
        QVERIFY2(follows, "the crosshair did not follow the handle");
        const QStringList letters = coronal->edgeLabels();
        QVERIFY2(letters[0].startsWith("R") && letters[1].startsWith("L") && letters[2] == "S" && letters[3] == "I",
                 qPrintable(letters.join(",")));
        saveArtifact("slices-crosshair-rotated.png");
        axial->setFocus();
        QTest::keyClick(axial, Qt::Key_O);
        for (auto* v : {axial, coronal, sagittal}) QCOMPARE(v->tiltDegrees(), 0.0);
    }

    // V makes a slice view follow the 3D view's direction (MedVis's re-slicing along the viewing
    // direction): the plane turns with the camera, its letters with it; O ends it.
    void sliceFollowsTheThreeDView() {
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        auto* axial = window_->slice(0);
        axial->setFocus();
        QTest::keyClick(axial, Qt::Key_V);
        QVERIFY(axial->followsView());
        window_->view()->setStandardView(core::OrbitCamera::Standard::Left);
        QTRY_VERIFY_WITH_TIMEOUT(std::abs(std::abs(glm::dot(axial->normal(), glm::dvec3(1, 0, 0))) - 1.0) < 1e-9, 20000);
        QStringList letters = axial->edgeLabels();
        QVERIFY2((QSet<QString>{letters[0], letters[1]} == QSet<QString>{"A", "P"}) && letters[2] == "S" && letters[3] == "I",
                 qPrintable(letters.join(",")));
        window_->view()->setStandardView(core::OrbitCamera::Standard::Anterior);
        QTRY_VERIFY_WITH_TIMEOUT(std::abs(std::abs(glm::dot(axial->normal(), glm::dvec3(0, 1, 0))) - 1.0) < 1e-9, 20000);
        letters = axial->edgeLabels();
        QVERIFY2(letters[0] == "R" && letters[1] == "L" && letters[2] == "S" && letters[3] == "I", qPrintable(letters.join(",")));
        saveArtifact("slice-along-3d-view.png");
        QTest::keyClick(axial, Qt::Key_O);
        QVERIFY(!axial->followsView());
        QCOMPARE(axial->tiltDegrees(), 0.0);
        window_->view()->setStandardView(core::OrbitCamera::Standard::Left);
        QTest::qWait(300);
        QCOMPARE(axial->tiltDegrees(), 0.0);  // no longer follows
    }

    // Left is never right: a bone block on the patient's left (+x in LPS) shows on the image's
    // right in the anterior 3D view and on the axial slice (radiological convention), and on the
    // image's left in the posterior 3D view.
    void patientsLeftIsOnTheImagesRightWhereItShouldBe() {
        core::VolumeGeometry g;
        g.dims = {64, 64, 48};
        g.spacing = {2.0, 2.0, 2.0};
        g.modality = "CT";
        g.scalarType = core::ScalarType::Int16;
        g.rescaleIntercept = -1024;
        test::DenseVolume v;
        v.dims = g.dims;
        v.values.assign(std::size_t(64) * 64 * 48, 0.0);  // air
        for (std::uint32_t k = 18; k < 30; ++k)
            for (std::uint32_t j = 26; j < 38; ++j)
                for (std::uint32_t i = 46; i < 58; ++i)  // +x: the patient's left
                    v.values[(std::size_t(k) * 64 + j) * 64 + i] = 2024.0;  // 1000 HU
        test::MemoryVoxelSource source(g, v);
        core::JobContext job;
        core::OctreeBuilder(core::BuildOptions{}).build(source, dir_.file("left.hvo"), job);
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("left.hvo"))));
        // The bright pixels' mean column, as a fraction of the image's width.
        const auto brightColumn = [](const QImage& img) {
            double sum = 0, n = 0;
            for (int y = 0; y < img.height(); ++y)
                for (int x = 0; x < img.width(); ++x)
                    if (qGray(img.pixel(x, y)) > 128) sum += x, n += 1;
            return n > 0 ? sum / n / img.width() : -1.0;
        };
        window_->view()->setStandardView(core::OrbitCamera::Standard::Anterior);
        const double anterior = brightColumn(settledFrame());
        QVERIFY2(anterior > 0.55, qPrintable(QString("anterior view: the left block at %1 of the width").arg(anterior)));
        window_->view()->setStandardView(core::OrbitCamera::Standard::Posterior);
        const double posterior = brightColumn(settledFrame());
        QVERIFY2(posterior >= 0 && posterior < 0.45, qPrintable(QString("posterior view: at %1 of the width").arg(posterior)));
        auto* axial = window_->slice(0);
        axial->setPoint(glm::dvec3(g.origin) + glm::dvec3(104, 64, 48));  // through the block
        const double slice = brightColumn(axial->image());
        QVERIFY2(slice > 0.55, qPrintable(QString("axial slice: at %1 of the width").arg(slice)));
        QCOMPARE(axial->edgeLabels()[1], QString("L"));
        axial->grab().save(kArtifacts + "/slice-left-block.png");
        window_->view()->setStandardView(core::OrbitCamera::Standard::Anterior);
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));  // what the next cases read
    }

    // Up/Down and Page keys step one and ten slices (the voxel spacing along the normal); ] makes
    // a thick slab whose MIP is nowhere darker than the thin slice and M its MinIP nowhere
    // brighter; the views say which slice and which octree level they show.
    void sliceViewStepsSlabsAndSaysItsLevel() {
        auto* axial = window_->slice(0);  // w-ct.hvo: 48 slices, 6.25 mm apart
        axial->setFocus();
        const double z = axial->point().z;
        QCOMPARE(axial->sliceStepMm(), 6.25);
        // With 48 slices the volume's centre lies between layers 23 and 24: the view shows an
        // acquired layer (it had shown the mean of the two), as it does after every step.
        const auto ct = core::OctreeReader::open(dir_.file("w-ct.hvo"));
        const glm::dmat4 toIndex = glm::inverse(ct->geometry().indexToPatient());
        const auto layer = [&] { return (toIndex * glm::dvec4(axial->plane().centre, 1.0)).z; };
        QVERIFY2(std::abs(layer() - std::round(layer())) < 1e-9, qPrintable(QString::number(layer())));
        QTest::keyClick(axial, Qt::Key_Up);
        QVERIFY2(std::abs(layer() - std::round(layer())) < 1e-9, qPrintable(QString::number(layer())));
        QCOMPARE(axial->point().z, z + 6.25);
        QCOMPARE(window_->slice(1)->point(), axial->point());  // the three views share the point
        QCOMPARE(window_->slice(2)->point(), axial->point());
        QWheelEvent wheel(QPointF(20, 20), axial->mapToGlobal(QPointF(20, 20)), QPoint(), QPoint(0, -120), Qt::NoButton,
                          Qt::NoModifier, Qt::NoScrollPhase, false);
        QApplication::sendEvent(axial, &wheel);
        QCOMPARE(axial->point().z, z);  // the wheel steps one slice back
        QTest::keyClick(axial, Qt::Key_Up);
        QTest::keyClick(axial, Qt::Key_PageDown);
        QVERIFY(std::abs(axial->point().z - (z + 6.25 - 62.5)) < 1e-9);
        QVERIFY2(axial->slicePosition().contains("/48"), qPrintable(axial->slicePosition()));
        QCOMPARE(axial->levelReadout(), QString("full resolution"));
        QTest::keyClick(axial, Qt::Key_PageUp);
        const QImage thin = axial->image();
        for (int i = 0; i < 3; ++i) QTest::keyClick(axial, Qt::Key_BracketRight);  // 5, 10, 20 mm
        QCOMPARE(axial->slabMm(), 20.0);
        const auto compare = [&](const QImage& slab, int sign) {  // sign 1: slab >= thin everywhere
            int wrong = 0, differ = 0;
            for (int y = 0; y < thin.height(); ++y)
                for (int x = 0; x < thin.width(); ++x) {
                    const int d = qGray(slab.pixel(x, y)) - qGray(thin.pixel(x, y));
                    wrong += d * sign < 0;
                    differ += d != 0;
                }
            return std::make_pair(wrong, differ);
        };
        const auto mip = compare(axial->image(), 1);
        QCOMPARE(mip.first, 0);
        QVERIFY2(mip.second > 100, "a 20 mm MIP shows more than the thin slice");
        QTest::keyClick(axial, Qt::Key_M);
        QCOMPARE(axial->slabMode(), core::SlabMode::MinIp);
        const auto minip = compare(axial->image(), -1);
        QCOMPARE(minip.first, 0);
        QVERIFY(minip.second > 100);
        saveArtifact("slab-minip.png");
        for (int i = 0; i < 3; ++i) QTest::keyClick(axial, Qt::Key_BracketLeft);
        QCOMPARE(axial->slabMm(), 0.0);
        QCOMPARE(compare(axial->image(), 1).second, 0);
        // Ctrl+Up tilts the axial plane about its horizontal axis, 5 degrees a press; the letters
        // follow (top anterior and, past about 17 degrees, superior or inferior too); O resets.
        for (int i = 0; i < 3; ++i) QTest::keyClick(axial, Qt::Key_Up, Qt::ControlModifier);
        QVERIFY2(std::abs(axial->tiltDegrees() - 15.0) < 1e-6, qPrintable(QString::number(axial->tiltDegrees())));
        QCOMPARE(axial->edgeLabels(), (QStringList{"R", "L", "A", "P"}));
        for (int i = 0; i < 5; ++i) QTest::keyClick(axial, Qt::Key_Up, Qt::ControlModifier);
        QVERIFY(std::abs(axial->tiltDegrees() - 40.0) < 1e-6);
        const QStringList tilted = axial->edgeLabels();
        QCOMPARE(tilted.mid(0, 2), (QStringList{"R", "L"}));
        QVERIFY2((tilted[2] == "AI" && tilted[3] == "PS") || (tilted[2] == "AS" && tilted[3] == "PI"),
                 qPrintable(tilted.join(",")));
        saveArtifact("slice-tilted.png");
        // Another volume opens on the standard plane, not on the last one's tilt.
        for (int i = 0; i < 3; ++i) QTest::keyClick(axial, Qt::Key_Up, Qt::ControlModifier);
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-mr.hvo"))));
        QCOMPARE(axial->tiltDegrees(), 0.0);
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("w-ct.hvo"))));
        axial->setFocus();
        for (int i = 0; i < 3; ++i) QTest::keyClick(axial, Qt::Key_Up, Qt::ControlModifier);
        QTest::keyClick(axial, Qt::Key_O);
        QCOMPARE(axial->tiltDegrees(), 0.0);
        QCOMPARE(axial->edgeLabels(), (QStringList{"R", "L", "A", "P"}));
        settledFrame();
        QVERIFY2(!view()->levelReadout().isEmpty(), "the 3D view says which levels it shows");
        QVERIFY2(!view()->levelReadout().contains("refining"), qPrintable(view()->levelReadout()));
    }

    void cleanupTestCase() { close(); }
};

int main(int argc, char** argv) { return test::runGuiTests<SliceNavigationTest>(argc, argv); }

#include "SliceNavigationTest.moc"
