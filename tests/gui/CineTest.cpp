// GUI tests of 4D cine under Xvfb (Qt Test): a dynamic series of ten time points written by
// pydicom (tests/support/dicom_cases.py: every voxel of time point v is 1000·v above time point
// 0's), opened on one time point from the Studies browser. The other time points are built in
// the background; the slider shows each with the slice plane, window and camera kept, and the
// value under the crosshair is that time point's own; play steps in a loop or back and forth;
// once every time point has been seen, a second pass reads no brick from disk (counted).
// Screenshot under <build>/test-artifacts/gui/cine.png.
#include <QSignalSpy>
#include <QTest>
#include <QTreeWidget>
#include <QTreeWidgetItemIterator>

#include <cmath>

#include "tests/gui/GuiTestSupport.h"
#include "tests/support/ProcessRunner.h"
#include "ui/CinePanel.h"
#include "ui/SliceView.h"
#include "ui/StudyBrowser.h"
#include "ui/VolumeView.h"

using namespace hvx;

class CineTest : public QObject, test::GuiFixture {
    Q_OBJECT

private slots:
    void initTestCase() {
        open();
        const auto r = test::runCommand("/usr/bin/python3 " HVX_SOURCE_DIR "/tests/support/dicom_cases.py " + dir_.file("cases"));
        QVERIFY2(r.exitCode == 0, r.output.c_str());
        QSignalSpy imported(window_->browser(), &ui::StudyBrowser::imported);
        window_->browser()->importPaths({QString::fromStdString(dir_.file("cases/dynamic"))});
        QTRY_COMPARE_WITH_TIMEOUT(imported.count(), 1, 60000);
    }

    void openingOneTimePointBuildsTheOthersForCine() {
        auto* tree = window_->browser()->tree();
        QTreeWidgetItem* third = nullptr;
        for (QTreeWidgetItemIterator it(tree); *it; ++it)
            if ((*it)->text(0) == "#3 time 3") third = *it;
        QVERIFY(third);
        tree->setFocus();
        tree->setCurrentItem(third);
        QTest::keyClick(tree, Qt::Key_Return);
        QVERIFY(window_->jobs()->waitIdle(180000));
        QTRY_VERIFY_WITH_TIMEOUT(!window_->openLabel().endsWith("(preview)"), 10000);
        auto* cine = window_->cine();
        QCOMPARE(cine->count(), 10);
        QCOMPARE(cine->current(), 2);
        for (int i = 0; i < 10; ++i) QVERIFY2(cine->isReady(i), qPrintable(cine->status()));
        QVERIFY2(cine->status().startsWith("3 of 10: #3 time 3"), qPrintable(cine->status()));
    }

    // Each time point in its own voxels, the plane, point, window and camera kept.
    void theSliderShowsEachTimePointInPlace() {
        auto* axial = window_->slice(0);
        const glm::dvec3 point = axial->point();
        const double centre = axial->windowCentre(), width = axial->windowWidth();
        const auto eye = view()->camera().view(64, 64).eye;
        const double atThird = axial->valueAtPoint();
        QVERIFY(std::isfinite(atThird));
        for (const int i : {0, 9, 4, 2}) {
            window_->cine()->setCurrent(i);
            QCOMPARE(view()->timePoint(), i);
            QVERIFY2(std::abs(axial->valueAtPoint() - atThird - 1000.0 * (i - 2)) < 1e-3,
                     qPrintable(QString("time point %1: %2 at the crosshair, %3 at time point 3").arg(i + 1)
                                    .arg(axial->valueAtPoint()).arg(atThird)));
            QCOMPARE(axial->point(), point);
            QCOMPARE(axial->windowCentre(), centre);
            QCOMPARE(axial->windowWidth(), width);
            QCOMPARE(view()->camera().view(64, 64).eye, eye);
            QVERIFY2(window_->openLabel().endsWith("#" + QString::number(i + 1) + " time " + QString::number(i + 1)),
                     qPrintable(window_->openLabel()));
        }
    }

    // Play: a loop wraps from the last time point to the first; bounce turns back at the end.
    void playLoopsAndBounces() {
        auto* cine = window_->cine();
        QSignalSpy chosen(cine, &ui::CinePanel::timePointChosen);
        cine->setCurrent(7);
        chosen.clear();
        cine->setFramesPerSecond(30);
        cine->setBounce(false);
        cine->setPlaying(true);
        QTRY_VERIFY_WITH_TIMEOUT(chosen.count() >= 3, 10000);
        cine->setPlaying(false);
        QCOMPARE(chosen.at(0).at(0).toInt(), 8);
        QCOMPARE(chosen.at(1).at(0).toInt(), 9);
        QCOMPARE(chosen.at(2).at(0).toInt(), 0);
        cine->setCurrent(8);
        chosen.clear();
        cine->setBounce(true);
        cine->setPlaying(true);
        QTRY_VERIFY_WITH_TIMEOUT(chosen.count() >= 3, 10000);
        cine->setPlaying(false);
        QCOMPARE(chosen.at(0).at(0).toInt(), 9);
        QCOMPARE(chosen.at(1).at(0).toInt(), 8);
        QCOMPARE(chosen.at(2).at(0).toInt(), 7);
    }

    // Once warm, cine never goes back to the disk: a second pass through the ten time points
    // reads no brick.
    void aWarmSecondPassReadsNoBrick() {
        auto* cine = window_->cine();
        for (int i = 0; i < 10; ++i) {
            cine->setCurrent(i);
            settledFrame();
        }
        const std::size_t warm = view()->bricksLoaded();
        for (int i = 0; i < 10; ++i) {
            cine->setCurrent(i);
            settledFrame();
        }
        qInfo("bricks read: %zu for the first pass through 10 time points, %zu more for the second", warm,
              view()->bricksLoaded() - warm);
        QVERIFY(warm > 0);
        QCOMPARE(view()->bricksLoaded(), warm);
        saveArtifact("cine.png");
    }

    // The 4D series' own row opens its first time point, with every other one in cine (not one
    // volume alone).
    void theSeriesRowOpensItsFirstTimePointWithCine() {
        auto* tree = window_->browser()->tree();
        QTreeWidgetItem* series = nullptr;
        for (QTreeWidgetItemIterator it(tree); *it; ++it)
            if ((*it)->text(0) == "#3 time 3") series = (*it)->parent();
        QVERIFY(series);
        tree->setFocus();
        tree->setCurrentItem(series);
        QTest::keyClick(tree, Qt::Key_Return);
        QVERIFY(window_->jobs()->waitIdle(180000));
        QTRY_VERIFY_WITH_TIMEOUT(!window_->openLabel().endsWith("(preview)"), 10000);
        auto* cine = window_->cine();
        QCOMPARE(cine->count(), 10);
        QCOMPARE(cine->current(), 0);
        QVERIFY2(cine->status().startsWith("1 of 10: #1 time"), qPrintable(cine->status()));
    }

    // Opening a DICOM folder (as `holovox --demo` opens the demo series, and File > Open does):
    // imported, opened, and its series selected in the browser, the row the open volume is.
    void anOpenedFolderIsSelectedInTheBrowser() {
        QVERIFY(window_->openPath(QString::fromStdString(dir_.file("cases/windows"))));
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(!window_->openLabel().endsWith("(preview)"), 10000);
        auto* item = window_->browser()->tree()->currentItem();
        QVERIFY(item);
        QCOMPARE(item->data(0, Qt::UserRole + 3).toString(), window_->openLabel());  // the row's label
        QCOMPARE(window_->cine()->count(), 0);  // one volume: nothing to play
    }

    void cleanupTestCase() { close(); }
};

int main(int argc, char** argv) { return test::runGuiTests<CineTest>(argc, argv); }

#include "CineTest.moc"
