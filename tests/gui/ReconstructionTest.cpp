// GUI tests of the 3D view's reconstruction choice under Xvfb (Qt Test; thesis ch. 4): a label
// map opens with split-voxels, built once in the background into the cache folder and drawn in
// the 3D view (its readout says so); nearest and split-voxels are switched without a rebuild and
// each volume keeps its choice; light-field frames draw what the view draws; an image starts as
// the Default menu says (trilinear unless changed), and split-voxels give way to its own
// octree in MIP; a volume split-voxels cannot be built for goes back to trilinear with the
// reason in the Jobs panel. Screenshot under <build>/test-artifacts/gui/reconstruction.png.
#include <QAction>
#include <QCheckBox>
#include <QSettings>
#include <QComboBox>
#include <QPushButton>
#include <QFileInfo>
#include <QSignalSpy>
#include <QStandardItemModel>
#include <QTest>

#include <glm/geometric.hpp>

#include "core/camera/DisplayModel.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/gui/GuiTestSupport.h"
#include "tests/support/ImageCompare.h"
#include "tests/support/MemoryVoxelSource.h"
#include "ui/ReconstructionComparison.h"
#include "ui/RenderControls.h"
#include "ui/SplitVoxelLink.h"

using namespace hvx;

namespace {

/// 96³ at 2 mm: a sphere of label 1 cut by an oblique plane, label 2 beyond it, 0 around.
test::MemoryVoxelSource labelSphere() {
    core::VolumeGeometry g;
    g.scalarType = core::ScalarType::UInt8;
    g.dims = {96, 96, 96};
    g.spacing = {2, 2, 2};
    g.modality = "SEG";
    g.isLabel = true;
    g.valueMax = 2;
    test::DenseVolume v;
    v.dims = g.dims;
    const glm::dvec3 c(47.5), n = glm::normalize(glm::dvec3(1, 0.4, 0.3));
    for (std::uint32_t k = 0; k < 96; ++k)
        for (std::uint32_t j = 0; j < 96; ++j)
            for (std::uint32_t i = 0; i < 96; ++i) {
                const glm::dvec3 p(i, j, k);
                v.values.push_back(glm::length(p - c) > 36 ? 0.0 : glm::dot(n, p - c) >= 0 ? 2.0 : 1.0);
            }
    return test::MemoryVoxelSource(g, v);
}
}  // namespace

class ReconstructionTest : public QObject, test::GuiFixture {
    Q_OBJECT

    QComboBox* box() const { return window_->findChild<QComboBox*>("reconstruction"); }
    ui::SplitVoxelLink* link() const { return window_->splitVoxels(); }
    QString file(const char* name) { return QString::fromStdString(dir_.file(name)); }
    /// Split-voxel builds among the jobs a spy on JobManager::started saw.
    static int builds(const QSignalSpy& started) {
        int n = 0;
        for (const auto& args : started) n += args.at(1).toString().startsWith("Split-voxels of");
        return n;
    }

private slots:
    void initTestCase() {
        open();
        auto labels = labelSphere();
        test::buildOctree(labels, dir_.file("labels.hvo"), true);
        core::PhantomVoxelSource ct({96, 96, 80});
        test::buildOctree(ct, dir_.file("ct.hvo"));
        core::PhantomVoxelSource ct2({48, 48, 40}, 2), ct3({48, 48, 40}, 3);
        test::buildOctree(ct2, dir_.file("ct2.hvo"));
        test::buildOctree(ct3, dir_.file("ct3.hvo"));
        // A float volume (split-voxels keep 8- and 16-bit integers only).
        core::VolumeGeometry g;
        g.scalarType = core::ScalarType::Float32;
        g.dims = {32, 32, 32};
        test::DenseVolume v;
        v.dims = g.dims;
        v.values.assign(32 * 32 * 32, 0.5);
        test::MemoryVoxelSource f(g, v);
        test::buildOctree(f, dir_.file("float.hvo"));
    }

    // Split-voxels by default for a label map: built once, drawn, said; nearest and back without
    // a rebuild; the choice and the built file kept when the volume is opened again.
    void labelMapsOpenWithSplitVoxels() {
        QSignalSpy started(window_->jobs(), &ui::JobManager::started);
        QVERIFY(window_->openPath(file("labels.hvo")));
        QCOMPARE(box()->currentIndex(), int(ui::RenderControls::Reconstruction::SplitVoxels));
        auto* model = qobject_cast<QStandardItemModel*>(box()->model());
        QVERIFY2(model && !model->item(0)->isEnabled(), "trilinear is not offered for labels");
        QTRY_VERIFY_WITH_TIMEOUT(link()->splitReader() != nullptr, 60000);
        QCOMPARE(builds(started), 1);
        const QString cached = ui::SplitVoxelLink::cachePath(file("labels.hvo"));
        QVERIFY2(QFileInfo::exists(cached), qPrintable(cached));
        QVERIFY2(!qEnvironmentVariable("XDG_CACHE_HOME").isEmpty() && cached.startsWith(qEnvironmentVariable("XDG_CACHE_HOME")),
                 qPrintable(cached + " is not in the test's own cache folder"));
        const QImage split = settledFrame();
        QVERIFY(view()->splitShown());
        QVERIFY2(view()->levelReadout().startsWith("split-voxels, cells of"), qPrintable(view()->levelReadout()));
        QVERIFY2(test::coverage(split) > 0.05, qPrintable(QString::number(test::coverage(split))));
        saveArtifact("reconstruction.png");

        // A light-field frame draws the split-voxels too (views of the 3D view's volume).
        const auto display = core::DisplayModel::load("looking-glass-portrait");
        const auto splitViews = view()->renderViews(display, 1.0, 1.0, 48 * 60 * 80);

        box()->setCurrentIndex(int(ui::RenderControls::Reconstruction::Nearest));
        const QImage nearest = settledFrame();
        const auto nearestViews = view()->renderViews(display, 1.0, 1.0, 48 * 60 * 80);
        QCOMPARE(splitViews.size(), std::size_t(48));
        const double views = test::psnr(splitViews[20], nearestViews[20]);
        QVERIFY2(views > 15.0 && views < 60.0, qPrintable(QString("split and nearest views %1 dB apart").arg(views)));
        QVERIFY(!view()->splitShown());
        QVERIFY2(!view()->levelReadout().contains("split"), qPrintable(view()->levelReadout()));
        // The same sphere, drawn from two octrees: close, not the same.
        const double d = test::difference(split, nearest);
        QVERIFY2(d > 0.0 && d < 12.0, qPrintable(QString::number(d)));

        box()->setCurrentIndex(int(ui::RenderControls::Reconstruction::SplitVoxels));
        settledFrame();
        QVERIFY(view()->splitShown());
        QCOMPARE(builds(started), 1);  // no rebuild

        QVERIFY(window_->openPath(file("ct.hvo")));
        QVERIFY(window_->openPath(file("labels.hvo")));
        QCOMPARE(box()->currentIndex(), int(ui::RenderControls::Reconstruction::SplitVoxels));
        QTRY_VERIFY_WITH_TIMEOUT(link()->splitReader() != nullptr, 10000);
        QCOMPARE(builds(started), 1);  // the file built before, reused
        settledFrame();
        QVERIFY(view()->splitShown());
    }

    // An image opens trilinear; split-voxels chosen are built and drawn in DVR, and give way to
    // the volume's own octree in MIP; the choice is the volume's own.
    void imagesKeepTheirOwnChoice() {
        QVERIFY(window_->openPath(file("ct.hvo")));
        QCOMPARE(box()->currentIndex(), int(ui::RenderControls::Reconstruction::Trilinear));
        box()->setCurrentIndex(int(ui::RenderControls::Reconstruction::SplitVoxels));
        QTRY_VERIFY_WITH_TIMEOUT(link()->splitReader() != nullptr, 60000);
        settledFrame();
        QVERIFY(view()->splitShown());
        window_->findChild<QComboBox*>("renderMode")->setCurrentIndex(2);  // MIP
        settledFrame();
        QVERIFY(!view()->splitShown());
        QVERIFY2(!view()->levelReadout().contains("split"), qPrintable(view()->levelReadout()));
        window_->findChild<QComboBox*>("renderMode")->setCurrentIndex(0);
        settledFrame();
        QVERIFY(view()->splitShown());
        QVERIFY(window_->openPath(file("labels.hvo")));
        QVERIFY(window_->openPath(file("ct.hvo")));
        QCOMPARE(box()->currentIndex(), int(ui::RenderControls::Reconstruction::SplitVoxels));
        // The preset: an image never opened before opens as the Default menu says.
        QVERIFY(window_->openPath(file("ct2.hvo")));
        QCOMPARE(box()->currentIndex(), int(ui::RenderControls::Reconstruction::Trilinear));
        window_->findChild<QAction*>("reconstructionDefault-nearest")->trigger();
        QVERIFY(window_->openPath(file("ct3.hvo")));
        QCOMPARE(box()->currentIndex(), int(ui::RenderControls::Reconstruction::Nearest));
        QVERIFY(window_->openPath(file("ct2.hvo")));  // chosen before (trilinear): kept
        QCOMPARE(box()->currentIndex(), int(ui::RenderControls::Reconstruction::Trilinear));
        window_->findChild<QAction*>("reconstructionDefault-trilinear")->trigger();
    }

    // Split-voxels cannot be built for a float volume: the Jobs panel says why in a sentence and
    // the choice goes back to trilinear, the view drawing the volume's own octree.
    void aBuildThatFailsGoesBackToTrilinear() {
        QSignalSpy finished(window_->jobs(), &ui::JobManager::finished);
        QVERIFY(window_->openPath(file("float.hvo")));
        box()->setCurrentIndex(int(ui::RenderControls::Reconstruction::SplitVoxels));
        // Other jobs (the histogram) end meanwhile: the build is the one that fails.
        const auto failure = [&] {
            for (const auto& args : finished)
                if (args.at(1).toString() == "failed") return args.at(2).toString();
            return QString();
        };
        QTRY_VERIFY_WITH_TIMEOUT(!failure().isEmpty(), 30000);
        const QString why = failure();
        QVERIFY2(why.contains("8- or 16-bit"), qPrintable(why));
        QCOMPARE(box()->currentIndex(), int(ui::RenderControls::Reconstruction::Trilinear));
        settledFrame();
        QVERIFY(!view()->splitShown());
        QVERIFY(!QFileInfo::exists(ui::SplitVoxelLink::cachePath(file("float.hvo"))));
    }

    // The thesis's Fig. 4.6 from the Rendering dock's Compare button: the CT phantom at one level
    // (voxels of 4) drawn trilinear, nearest and as split-voxels, side by side: three different
    // images of the same body.
    void compareShowsOneLevelThreeWays() {
        QVERIFY(window_->openPath(file("ct.hvo")));
        settledFrame();
        window_->findChild<QPushButton*>("compareReconstructions")->click();
        auto* dialog = window_->findChild<ui::ReconstructionComparison*>();
        QVERIFY(dialog);
        QTRY_VERIFY_WITH_TIMEOUT(!dialog->image(2).isNull(), 60000);
        QTRY_VERIFY_WITH_TIMEOUT(dialog->renderedCount() > 0, 10000);
        dialog->grab().save(test::guiArtifacts() + "/reconstruction-compare.png");
        for (int i = 0; i < 3; ++i)
            QVERIFY2(test::coverage(dialog->image(i)) > 0.01,
                     qPrintable(QString("image %1 covers %2").arg(i).arg(test::coverage(dialog->image(i)))));
        const double dTN = test::difference(dialog->image(0), dialog->image(1)),
                     dNS = test::difference(dialog->image(1), dialog->image(2));
        QVERIFY2(dTN > 0.2 && dNS > 0.2, qPrintable(QString("trilinear-nearest %1, nearest-split %2").arg(dTN).arg(dNS)));
        QVERIFY2(dTN < 40 && dNS < 40, qPrintable(QString("trilinear-nearest %1, nearest-split %2").arg(dTN).arg(dNS)));
        const int before = dialog->renderedCount();
        dialog->setVoxels(8);
        QCOMPARE(dialog->renderedCount(), before + 1);
        QVERIFY(test::difference(dialog->image(2), dialog->image(1)) > 0.2);
        dialog->setVoxels(16);  // coarser than the octree's root: said, not drawn
        QCOMPARE(dialog->renderedCount(), before + 1);
        QVERIFY2(dialog->statusText().contains("coarser than its root"), qPrintable(dialog->statusText()));
        dialog->close();
    }

    // The Rendering dock's "Moving: rebuild from sub-frames" (thesis §3.3): while the view is
    // dragged, each frame draws one quincunx sub-frame and the image is rebuilt from the last
    // four; once still, the frame is whole and the same as with the option off. Remembered.
    void movingFramesRebuiltFromSubFrames() {
        QVERIFY(window_->openPath(file("ct.hvo")));
        auto* box = window_->findChild<QCheckBox*>("frameReconstruction");
        QVERIFY(box);
        QVERIFY2(!box->isChecked() && !view()->frameReconstruction(), "off unless chosen");
        const QImage whole = settledFrame();
        box->setChecked(true);
        QVERIFY(view()->frameReconstruction());
        QVERIFY(QSettings().value("view/frameReconstruction").toBool());
        const QPoint c = view()->rect().center();
        QTest::mousePress(view(), Qt::LeftButton, {}, c);
        int rebuilt = 0;
        for (int i = 1; i <= 8; ++i) {
            const int before = view()->frameCount();
            QTest::mouseMove(view(), c + QPoint(6 * i, 0));
            QTRY_VERIFY_WITH_TIMEOUT(view()->frameCount() > before, 10000);
            rebuilt += view()->readouts().subFrame;
            QVERIFY2(test::coverage(view()->lastFrame()) > 0.02, "a rebuilt frame shows the volume");
        }
        QVERIFY2(rebuilt >= 6, qPrintable(QString("%1 of 8 moving frames rebuilt from sub-frames").arg(rebuilt)));
        view()->grab().save(test::guiArtifacts() + "/subframes-moving.png");
        // Back where it started, then still: a whole frame, as without the option.
        QTest::mouseMove(view(), c);
        QTest::mouseRelease(view(), Qt::LeftButton, {}, c);
        const QImage still = settledFrame();
        QVERIFY(!view()->readouts().subFrame);
        QVERIFY2(test::difference(still, whole) < 0.5, qPrintable(QString("still frame differs by %1").arg(test::difference(still, whole))));
        box->setChecked(false);
        QVERIFY(!view()->frameReconstruction());
    }

    void cleanupTestCase() { close(); }
};

int main(int argc, char** argv) { return test::runGuiTests<ReconstructionTest>(argc, argv); }
#include "ReconstructionTest.moc"
