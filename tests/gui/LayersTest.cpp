// GUI tests of the Layers dock under Xvfb (Qt Test): a second volume on a rotated, anisotropic
// grid laid over the open one in colour, its marker where the patient point is; a label map with
// a Slicer colour table, its legend and per-label visibility; a partner from another frame of
// reference refused until forced; a series laid over from the Studies browser's menu, its octree
// built first. Screenshot under <build>/test-artifacts/gui/layers.png.
#include <QCheckBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFile>
#include <QLabel>
#include <QSignalSpy>
#include <QTest>
#include <QTreeWidget>
#include <QTreeWidgetItemIterator>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>

#include "core/camera/DisplayModel.h"
#include "core/octree/OctreeBuilder.h"
#include "ui/ImageConversion.h"
#include "dicom/DicomSeriesWriter.h"
#include "tests/gui/GuiTestSupport.h"
#include "tests/support/MemoryVoxelSource.h"
#include "tests/support/ProcessRunner.h"
#include "ui/LayersPanel.h"
#include "ui/SliceLayers.h"
#include "ui/SliceView.h"
#include "ui/StudyBrowser.h"
#include "ui/TransferFunctionEditor.h"

using namespace hvx;

namespace {
const std::string kFrame = "1.2.826.0.1.3680043.9.7777.50";
const glm::dvec3 kHotSpot(10, -20, 6);    // the overlay's marker (LPS mm)
const glm::dvec3 kLiver(-30, 10, 0);      // label 1's centre

/// A volume centred on the LPS origin, value f(patient point) at each voxel.
template <class F>
test::MemoryVoxelSource volume(std::array<std::uint32_t, 3> dims, glm::dvec3 spacing, glm::dmat3 direction,
                               core::ScalarType type, const std::string& modality, std::string frame, F f) {
    core::VolumeGeometry g;
    g.scalarType = type;
    g.spacing = spacing;
    g.direction = direction;
    g.origin = -(direction * ((glm::dvec3(dims[0], dims[1], dims[2]) - 1.0) * spacing / 2.0));
    g.modality = modality;
    g.frameOfReferenceUid = std::move(frame);
    g.dims = dims;
    test::DenseVolume v;
    v.dims = dims;
    for (std::uint32_t k = 0; k < dims[2]; ++k)
        for (std::uint32_t j = 0; j < dims[1]; ++j)
            for (std::uint32_t i = 0; i < dims[0]; ++i) v.values.push_back(f(glm::dvec3(g.indexToPatient() * glm::dvec4(i, j, k, 1.0))));
    return test::MemoryVoxelSource(g, v);
}


double hot(const glm::dvec3& p) { return 10 * std::exp(-glm::dot(p - kHotSpot, p - kHotSpot) / (2 * 36.0)); }

std::array<int, 3> rgbAt(const QImage& img, QPointF at) {
    const QColor c = img.pixelColor(at.toPoint());
    return {c.red(), c.green(), c.blue()};
}
}  // namespace

class LayersTest : public QObject, test::GuiFixture {
    Q_OBJECT

    std::unique_ptr<test::MemoryVoxelSource> labels_;
    ui::SliceView* axial() const { return window_->slice(0); }
    /// 12 mm beside the marker the overlay is in hot's red part: red over the base's grey.
    void expectRedAround(const glm::dvec3& marker, const QImage& base) {
        const QPointF at = axial()->widgetAt(marker + glm::dvec3(12, 0, 0));
        const auto c = rgbAt(axial()->image(), at);
        QVERIFY2(c[0] > c[2] + 20 && c[0] != qRed(base.pixel(at.toPoint())),
                 qPrintable(QString("%1 %2 %3").arg(c[0]).arg(c[1]).arg(c[2])));
    }
    void pointAt(const glm::dvec3& p) {
        for (int i = 0; i < 3; ++i) window_->slice(i)->setPoint(p);
    }

    /// Liver-red and spleen-blue pixels of the 3D frame (hues, whatever the shading).
    std::pair<int, int> organPixels(const QImage& frame) {
        int liver = 0, spleen = 0;
        for (int y = 0; y < frame.height(); ++y)
            for (int x = 0; x < frame.width(); ++x) {
                const QColor c = frame.pixelColor(x, y);
                if (c.red() > c.blue() + 30 && std::abs(c.green() - c.blue()) <= 12) ++liver;
                else if (c.blue() > c.red() + 30 && std::abs(c.green() - c.red()) <= 12) ++spleen;
            }
        return {liver, spleen};
    }

    // The labels laid over the CT are marched with it in the 3D view, in their table's colours;
    // a label hidden in the legend leaves the 3D view too; "Show in the 3D view" off leaves the
    // CT alone.
    void labelsAreFusedIn3D() {
        auto* show3D = window_->layersPanel()->findChild<QCheckBox*>();
        for (auto* box : window_->layersPanel()->findChildren<QCheckBox*>())
            if (box->text().contains("3D")) show3D = box;
        QVERIFY(show3D && show3D->text().contains("3D") && show3D->isChecked());
        const QImage fused = settledFrame();
        fused.save(test::guiArtifacts() + "/layers-fused-3d.png");
        const auto [liver, spleen] = organPixels(fused);
        QVERIFY2(liver > 300 && spleen > 50, qPrintable(QString("liver %1, spleen %2 pixels").arg(liver).arg(spleen)));
        auto* legend = window_->layersPanel()->findChild<QTreeWidget*>("labelLegend");
        legend->topLevelItem(0)->setCheckState(0, Qt::Unchecked);  // liver hidden
        const auto hidden = organPixels(settledFrame());
        QVERIFY2(hidden.first < liver / 20 && hidden.second > spleen / 2,
                 qPrintable(QString("liver hidden: liver %1, spleen %2 pixels").arg(hidden.first).arg(hidden.second)));
        legend->topLevelItem(0)->setCheckState(0, Qt::Checked);
        // A light-field frame fuses them too: the organs' hues in a middle view.
        const auto views = view()->renderViews(core::DisplayModel::load("looking-glass-portrait"), 1.0, 1.0, 48 * 120 * 160);
        const auto [lfLiver, lfSpleen] = organPixels(ui::toQImage(views[views.size() / 2]));
        QVERIFY2(lfLiver > 30 && lfSpleen > 5, qPrintable(QString("light field: liver %1, spleen %2 pixels").arg(lfLiver).arg(lfSpleen)));
        show3D->setChecked(false);
        const auto alone = organPixels(settledFrame());
        QVERIFY2(alone.first < liver / 20 && alone.second < spleen / 20,
                 qPrintable(QString("not in 3D: liver %1, spleen %2 pixels").arg(alone.first).arg(alone.second)));
        show3D->setChecked(true);
    }

private slots:
    void initTestCase() {
        open();
        auto ct = volume({96, 96, 64}, {2, 2, 2}, glm::dmat3(1.0), core::ScalarType::Int16, "CT", kFrame,
                         [](const glm::dvec3&) { return 40.0; });
        test::buildOctree(ct, dir_.file("ct.hvo"));
        const glm::dmat3 rot(glm::rotate(glm::dmat4(1.0), glm::radians(25.0), glm::normalize(glm::dvec3(0.3, 1, 2))));
        auto pet = volume({50, 40, 24}, {2.5, 3.1, 4.0}, rot, core::ScalarType::Float32, "PT", kFrame, hot);
        test::buildOctree(pet, dir_.file("pet.hvo"));
        auto elsewhere = volume({50, 40, 24}, {2.5, 3.1, 4.0}, rot, core::ScalarType::Float32, "PT", kFrame + ".9", hot);
        test::buildOctree(elsewhere, dir_.file("elsewhere.hvo"));
        labels_ = std::make_unique<test::MemoryVoxelSource>(volume({48, 48, 32}, {4, 4, 4}, glm::dmat3(1.0), core::ScalarType::UInt8, "SEG", kFrame,
                             [](const glm::dvec3& p) {
                                 if (glm::length(p - kLiver) < 14) return 1.0;
                                 if (std::abs(p.x - 40) < 8 && std::abs(p.y) < 8 && std::abs(p.z) < 8) return 2.0;
                                 return 0.0;
                             }));
        test::buildOctree(*labels_, dir_.file("labels.hvo"), true);
        std::ofstream(dir_.file("organs.ctbl")) << "# Color table file organs.ctbl\n0 Background 0 0 0 0\n"
                                                   "1 liver 200 60 60 255\n2 spleen 60 60 200 255\n";
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("ct.hvo"))));
    }

    void overlayMarkerLandsOnItsPatientPoint() {
        auto* panel = window_->layersPanel();
        pointAt(kHotSpot);
        const QImage before = axial()->image();
        QVERIFY2(panel->chooseOverlay(QString::fromStdString(dir_.file("pet.hvo")), "PET"), qPrintable(panel->message()));
        QVERIFY(window_->layers()->hasOverlay());
        const QImage img = axial()->image();
        QCOMPARE(img.size(), before.size());
        // The overlay's brightest part (hot: white at the top) is centred on the marker's point.
        int best = 0;
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) best = std::max(best, img.pixelColor(x, y).blue());
        double sx = 0, sy = 0, n = 0;
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x)
                if (img.pixelColor(x, y).blue() >= best - 10) sx += x + 0.5, sy += y + 0.5, ++n;
        const QPointF want = axial()->widgetAt(kHotSpot);
        QVERIFY2(std::hypot(sx / n - want.x(), sy / n - want.y()) < 1.0,
                 qPrintable(QString("peak at %1,%2, marker at %3,%4").arg(sx / n).arg(sy / n).arg(want.x()).arg(want.y())));
        expectRedAround(kHotSpot, before);
        // Far from the marker the overlay has nothing: the base's grey, untouched.
        const QPointF far = axial()->widgetAt(kHotSpot + glm::dvec3(-60, 30, 0));
        QCOMPARE(img.pixelColor(far.toPoint()), before.pixelColor(far.toPoint()));
        // A window of small values (an ADC map's 0.0025 mm²/s) keeps its width in the panel's
        // boxes, and editing the level does not send a width of 0 (two decimals had).
        const core::DisplayWindow chosen = window_->layers()->overlayWindow();
        window_->layers()->setOverlayWindow({"", 0.004, 0.0025});
        QDoubleSpinBox* width = nullptr;
        QDoubleSpinBox* level = nullptr;
        for (auto* box : panel->findChildren<QDoubleSpinBox*>()) (width ? level : width) = box;
        QVERIFY(width && level);
        QVERIFY2(std::abs(width->value() - 0.0025) < 1e-9, qPrintable(width->text()));
        level->setValue(0.005);
        QVERIFY2(std::abs(window_->layers()->overlayWindow().width - 0.0025) < 1e-9,
                 qPrintable(QString::number(window_->layers()->overlayWindow().width)));
        QVERIFY(std::abs(window_->layers()->overlayWindow().centre - 0.005) < 1e-9);
        window_->layers()->setOverlayWindow(chosen);
        QVERIFY(std::abs(width->value() - chosen.width) <= 1e-3 * chosen.width);  // shown to four digits
        // Opacity 0: the slice is the base again.
        window_->layers()->setOverlayOpacity(0.0);
        QCOMPARE(axial()->image().convertToFormat(QImage::Format_RGB888), before.convertToFormat(QImage::Format_RGB888));
        window_->layers()->setOverlayOpacity(0.5);
    }

    void labelsTakeTheirTablesColoursAndHideByLegend() {
        auto* panel = window_->layersPanel();
        pointAt(kLiver);
        QVERIFY2(panel->chooseLabels(QString::fromStdString(dir_.file("labels.hvo")), "organs"), qPrintable(panel->message()));
        QVERIFY2(panel->chooseLabelTable(QString::fromStdString(dir_.file("organs.ctbl"))), qPrintable(panel->message()));
        const QPointF at = axial()->widgetAt(kLiver);
        // Fill at 50 % over the base's grey (40 HU in W 400 / L 40: 128): (164, 94, 94).
        const auto c = rgbAt(axial()->image(), at);
        QVERIFY2(std::abs(c[0] - 164) <= 2 && std::abs(c[1] - 94) <= 2 && std::abs(c[2] - 94) <= 2,
                 qPrintable(QString("%1 %2 %3").arg(c[0]).arg(c[1]).arg(c[2])));
        auto* legend = panel->findChild<QTreeWidget*>("labelLegend");
        QVERIFY(legend);
        QCOMPARE(legend->topLevelItemCount(), 2);
        QCOMPARE(legend->topLevelItem(0)->text(1), QString("liver"));
        QCOMPARE(legend->topLevelItem(1)->text(1), QString("spleen"));
        // Statistics per label: the liver sphere's voxels of the 4 mm grid, over a CT of 40 HU.
        std::size_t liverVoxels = 0;
        for (const double v : labels_->values().values) liverVoxels += v == 1.0;
        const int id = panel->computeStatistics();
        QVERIFY(id >= 0);
        QVERIFY(window_->jobs()->waitIdle(60000));
        QTRY_COMPARE(legend->topLevelItem(0)->text(2), QString::number(double(liverVoxels) * 64 / 1000.0, 'f', 2));
        QCOMPARE(legend->topLevelItem(0)->text(3), QString("40.0 \u00b1 0.0 HU"));
        QVERIFY(panel->exportStatistics(QString::fromStdString(dir_.file("stats.csv"))));
        QFile csv(QString::fromStdString(dir_.file("stats.csv")));
        QVERIFY(csv.open(QIODevice::ReadOnly));
        const QString text = QString::fromUtf8(csv.readAll());
        QVERIFY2(text.startsWith("label,name,voxels,volume_ml") && text.contains(QString("1,\"liver\",%1,").arg(liverVoxels)),
                 qPrintable(text));
        if (auto* dock = window_->findChild<QDockWidget*>("layersDock")) dock->raise();
        QTest::qWait(50);
        saveArtifact("layers.png");
        window_->slice(0)->grab().save(test::guiArtifacts() + "/layers-axial.png");
        legend->topLevelItem(0)->setCheckState(0, Qt::Unchecked);  // liver hidden
        const auto hidden = rgbAt(axial()->image(), at);
        QCOMPARE(hidden[0], hidden[1]);
        QCOMPARE(hidden[1], hidden[2]);
        legend->topLevelItem(0)->setCheckState(0, Qt::Checked);
        // A broken table is refused and the colours stay.
        std::ofstream(dir_.file("broken.ctbl")) << "1 liver 200 60 60 255\n1 again 1 2 3 255\n";
        QVERIFY(!panel->chooseLabelTable(QString::fromStdString(dir_.file("broken.ctbl"))));
        QVERIFY2(panel->message().contains("already given on line 1"), qPrintable(panel->message()));
        QCOMPARE(rgbAt(axial()->image(), at), c);
        // An intensity volume is not a label map.
        QVERIFY(!panel->chooseLabels(QString::fromStdString(dir_.file("pet.hvo"))));
        QVERIFY(panel->message().contains("not a label map"));
        labelsAreFusedIn3D();
        window_->layers()->clearLabels();
    }

    void anotherFrameIsRefusedUntilForced() {
        auto* panel = window_->layersPanel();
        window_->layers()->clearOverlay();
        pointAt(kHotSpot);
        const QImage before = axial()->image();
        QVERIFY(!panel->chooseOverlay(QString::fromStdString(dir_.file("elsewhere.hvo"))));
        QVERIFY2(panel->message().contains("different frames of reference"), qPrintable(panel->message()));
        QVERIFY(!window_->layers()->hasOverlay());
        QCOMPARE(axial()->image(), before);
        auto* force = panel->findChild<QCheckBox*>();
        QVERIFY(force && force->text().contains("another frame"));
        force->setChecked(true);
        QVERIFY(panel->chooseOverlay(QString::fromStdString(dir_.file("elsewhere.hvo"))));
        force->setChecked(false);
        window_->layers()->clearOverlay();
    }

    void aSeriesIsLaidOverFromTheStudiesBrowser() {
        // The PET written as DICOM in the CT's frame, imported, then laid over from the menu:
        // its octree is built first, then it is laid over.
        const glm::dmat3 rot(glm::rotate(glm::dmat4(1.0), glm::radians(25.0), glm::normalize(glm::dvec3(0.3, 1, 2))));
        auto pet = volume({50, 40, 24}, {2.5, 3.1, 4.0}, rot, core::ScalarType::Int16, "PT", kFrame,
                          [](const glm::dvec3& p) { return std::round(100 * hot(p)); });
        dicom::DicomWriteOptions o;
        o.frameOfReferenceUid = kFrame;
        o.modality = "PT";
        core::JobContext job;
        dicom::DicomSeriesWriter::write(pet, dir_.file("pet-dicom"), o, job);
        QSignalSpy imported(window_->browser(), &ui::StudyBrowser::imported);
        window_->browser()->importPaths({QString::fromStdString(dir_.file("pet-dicom"))});
        QTRY_COMPARE_WITH_TIMEOUT(imported.count(), 1, 60000);
        QTreeWidgetItem* series = nullptr;
        for (QTreeWidgetItemIterator it(window_->browser()->tree()); *it; ++it)
            if (!(*it)->data(0, Qt::UserRole + 1).toString().isEmpty()) series = *it;
        QVERIFY(series);
        pointAt(kHotSpot);
        const QImage base = axial()->image();
        window_->browser()->requestOverlay(series);
        QTRY_VERIFY2_WITH_TIMEOUT(window_->layers()->hasOverlay(), qPrintable(window_->layersPanel()->message()), 60000);
        QVERIFY(window_->jobs()->waitIdle(60000));
        expectRedAround(kHotSpot, base);
        QVERIFY(window_->layers()->note().isEmpty());  // the same frame: nothing to say
    }

    void aSegmentationSeriesIsLaidOverItsImage() {
        // A CT, its DICOM SEG and RTSTRUCT written by pydicom, imported together: the CT opened,
        // then the SEG series opened lays its segments over it with their own names and colours.
        const auto seg = dir_.file("seg");
        std::filesystem::create_directories(seg);
        QCOMPARE(test::runCommand("/usr/bin/python3 " HVX_SOURCE_DIR "/tests/support/seg_cases.py " + seg).exitCode, 0);
        window_->layers()->clearLabels();
        window_->layers()->clearOverlay();
        QSignalSpy imported(window_->browser(), &ui::StudyBrowser::imported);
        window_->browser()->importPaths({QString::fromStdString(seg)});
        QTRY_COMPARE_WITH_TIMEOUT(imported.count(), 1, 60000);
        QTreeWidgetItem *ct = nullptr, *binary = nullptr;
        for (QTreeWidgetItemIterator it(window_->browser()->tree()); *it; ++it) {
            if ((*it)->data(0, Qt::UserRole + 1).toString().isEmpty()) continue;
            if ((*it)->text(2) == "CT" && (*it)->text(0).contains("CT")) ct = *it;
            if ((*it)->text(2) == "SEG" && (*it)->text(0).startsWith("300 ")) binary = *it;
        }
        QVERIFY(ct && binary);
        QVERIFY(binary->toolTip(0).contains("segmentation"));
        QCOMPARE(binary->parent(), ct);  // listed under the image series it was drawn on
        const QString binaryUid = binary->data(0, Qt::UserRole + 1).toString();
        window_->openSeries(ct->data(0, Qt::UserRole + 1).toString(), {}, "seg CT");
        QVERIFY(window_->jobs()->waitIdle(120000));
        QTRY_VERIFY_WITH_TIMEOUT(window_->openLabel() == "seg CT", 10000);
        std::ifstream ballFile(seg + "/ball.txt");
        glm::dvec3 ball;
        ballFile >> ball.x >> ball.y >> ball.z;
        pointAt(ball);
        // The browser's rows are made again when the CT's octree is recorded: find the SEG's anew.
        binary = window_->browser()->seriesItem(binaryUid);
        QVERIFY(binary);
        auto* tree = window_->browser()->tree();
        tree->setFocus();
        tree->setCurrentItem(binary);
        QTest::keyClick(tree, Qt::Key_Return);  // activates the row, as a double-click does
        QTRY_VERIFY2_WITH_TIMEOUT(window_->layers()->hasLabels(), qPrintable(window_->layersPanel()->message()), 60000);
        QVERIFY(window_->jobs()->waitIdle(60000));
        const auto& table = window_->layers()->labelTable();
        QVERIFY(table.find(1) && table.find(2));
        QCOMPARE(QString::fromStdString(table.find(1)->name), QString("liver"));
        const auto& liver = table.find(1)->rgba;
        const auto c = rgbAt(axial()->image(), axial()->widgetAt(ball));
        for (int a = 0; a < 3; ++a)  // half the liver's colour over 40 HU's grey (128)
            QVERIFY2(std::abs(c[std::size_t(a)] - (128 + (liver[std::size_t(a)] - 128) / 2.0)) <= 2.0,
                     qPrintable(QString("%1 %2 %3").arg(c[0]).arg(c[1]).arg(c[2])));
        window_->slice(0)->grab().save(test::guiArtifacts() + "/layers-seg-axial.png");

        // The structure set of the same import: its contours drawn onto the open CT's grid, its
        // ROIs' names in the table, the contour past the image said in the dock.
        window_->layers()->clearLabels();
        QTreeWidgetItem* rt = nullptr;
        for (QTreeWidgetItemIterator it(tree); *it; ++it)
            if ((*it)->text(2) == "RTSTRUCT") rt = *it;
        QVERIFY(rt);
        QVERIFY(rt->toolTip(0).contains("structure set"));
        QCOMPARE(rt->parent()->text(2), QString("CT"));
        tree->setCurrentItem(rt);
        QTest::keyClick(tree, Qt::Key_Return);
        QTRY_VERIFY2_WITH_TIMEOUT(window_->layers()->hasLabels(), qPrintable(window_->layersPanel()->message()), 60000);
        QVERIFY(window_->jobs()->waitIdle(60000));
        QCOMPARE(QString::fromStdString(window_->layers()->labelTable().find(1)->name), QString("GTV"));
        QCOMPARE(QString::fromStdString(window_->layers()->labelTable().find(2)->name), QString::fromUtf8("R\u00fcckenmark"));
        QVERIFY2(window_->layersPanel()->message().contains("past the image's slices"),
                 qPrintable(window_->layersPanel()->message()));
    }

    // A label map opened on its own: the 3D view draws each label in its table's colour (the
    // table kept beside the octree), the transfer function editor stands aside, and no pixel
    // takes a colour of neither label (a blend of the spleen's edge with the background would
    // pass through the liver's red on an ordinary ramp).
    void aLabelMapOpenedAloneIsDrawnIn3DInItsColours() {
        const auto octree = dir_.file("labels.hvo");
        std::filesystem::copy_file(dir_.file("organs.ctbl"), octree + ".ctbl", std::filesystem::copy_options::overwrite_existing);
        QVERIFY(window_->openOctree(QString::fromStdString(octree)));
        const QImage frame = settledFrame();
        QVERIFY(!window_->tfEditor()->isEnabled());
        int liver = 0, spleen = 0, other = 0;
        for (int y = 0; y < frame.height(); ++y)
            for (int x = 0; x < frame.width(); ++x) {
                const QColor c = frame.pixelColor(x, y);
                if (std::max({c.red(), c.green(), c.blue()}) < 24) continue;  // background
                if (c.red() > c.blue() + 30 && std::abs(c.green() - c.blue()) <= 12) ++liver;
                else if (c.blue() > c.red() + 30 && std::abs(c.green() - c.red()) <= 12) ++spleen;
                else ++other;
            }
        frame.save(test::guiArtifacts() + "/layers-labels-3d.png");
        QVERIFY2(liver > 500 && spleen > 100 && other <= (liver + spleen) / 200,
                 qPrintable(QString("liver %1, spleen %2, other %3 pixels").arg(liver).arg(spleen).arg(other)));
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("ct.hvo"))));
        QVERIFY(window_->tfEditor()->isEnabled());
    }

    void cleanupTestCase() { close(); }
};

int main(int argc, char** argv) { return test::runGuiTests<LayersTest>(argc, argv); }

#include "LayersTest.moc"
