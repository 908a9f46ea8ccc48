#pragma once
// What the GUI test programs share: the artefact folder, image comparisons, a settled 3D frame,
// the main window as the tests open it, and the program's start (OpenGL 4.5 core, a
// QApplication under its own organisation name, so that QSettings stays the tests').
#include <QApplication>
#include <QDir>
#include <QImage>
#include <QMouseEvent>
#include <QSettings>
#include <QTest>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/octree/OctreeBuilder.h"
#include "core/volume/PhantomVoxelSource.h"
#include "dicom/DicomSeriesWriter.h"
#include "tests/support/TempDir.h"
#include "ui/JobManager.h"
#include "ui/MainWindow.h"
#include "ui/VolumeView.h"

namespace hvx::test {

/// Where the GUI tests keep their screenshots: <build>/test-artifacts/gui (made on first use).
inline QString guiArtifacts() {
    const QString dir = QStringLiteral(HVX_BINARY_DIR "/test-artifacts/gui");
    QDir().mkpath(dir);
    return dir;
}

/// Builds `path` from `source` in bricks of 16 (several bricks and levels for small test volumes).
inline void buildOctree(core::VoxelSource& source, const std::string& path, bool labels = false) {
    core::BuildOptions o;
    o.brickSize = 16;
    o.labels = labels;
    core::JobContext job;
    core::OctreeBuilder(o).build(source, path, job);
}

/// The CT phantom the reading tests measure and step through: 48³ voxels over 300 mm (6.25 mm
/// apart), seed 5.
inline core::PhantomVoxelSource readingCtPhantom() {
    return core::PhantomVoxelSource({48, 48, 48}, 5, {300, 300, 300}, 5.0);
}

/// Writes a phantom series of 48 slices of 64² as DICOM files into `folder` for `patient` (also
/// its ID, cut to 8 characters) and returns their paths.
inline std::vector<std::string> writeSeries(const std::string& folder, const std::string& patient, unsigned seed,
                                            const std::string& studyDate = {}) {
    core::PhantomVoxelSource phantom({64, 64, 48}, seed, {400, 400, 400}, 5.0);
    dicom::DicomWriteOptions o;
    o.patientName = patient;
    o.studyDate = studyDate;
    o.patientId = patient.substr(0, 8);
    o.studyDescription = "GUI test";
    o.seriesDescription = "Phantom";
    core::JobContext job;
    return dicom::DicomSeriesWriter::write(phantom, folder, o, job);
}

/// PSNR (dB) of two RGB images of one size; 99 when equal.
inline double psnr(const QImage& a, const QImage& b) {
    double se = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const QRgb p = a.pixel(x, y), q = b.pixel(x, y);
            for (const int d : {qRed(p) - qRed(q), qGreen(p) - qGreen(q), qBlue(p) - qBlue(q)}) se += double(d) * d;
        }
    const double mse = se / (3.0 * a.width() * a.height()) / (255.0 * 255.0);
    return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0;
}

/// Fraction of pixels that are not black.
inline double coverage(const QImage& img) {
    std::size_t lit = 0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) lit += (img.pixel(x, y) & 0xFFFFFF) != 0;
    return double(lit) / double(std::max(1, img.width() * img.height()));
}

/// Mean absolute difference per channel (0..255) of two images of the same size (255 otherwise).
inline double difference(const QImage& a, const QImage& b) {
    if (a.size() != b.size()) return 255.0;
    double sum = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const QRgb p = a.pixel(x, y), q = b.pixel(x, y);
            sum += std::abs(qRed(p) - qRed(q)) + std::abs(qGreen(p) - qGreen(q)) + std::abs(qBlue(p) - qBlue(q));
        }
    return sum / (3.0 * a.width() * a.height());
}

/// A left-button drag from `from` to `to` with `modifiers` held: press, one move, release.
inline void leftDrag(QWidget* w, QPoint from, QPoint to, Qt::KeyboardModifiers modifiers = Qt::NoModifier) {
    QTest::mousePress(w, Qt::LeftButton, modifiers, from);
    QMouseEvent move(QEvent::MouseMove, QPointF(to), w->mapToGlobal(QPointF(to)), Qt::NoButton, Qt::LeftButton, modifiers);
    QApplication::sendEvent(w, &move);
    QTest::mouseRelease(w, Qt::LeftButton, modifiers, to);
}

/// Waits until the view has drawn a complete, full-quality frame after the last change, and
/// returns it (a timeout is reported as the calling test's failure).
inline QImage settledFrame(ui::VolumeView* view) {
    const int start = view->frameCount();
    view->update();
    [&] { QTRY_VERIFY_WITH_TIMEOUT(view->frameCount() > start && view->readouts().complete &&
                                       view->readouts().resolution >= 1.0, 60000); }();
    QTest::qWait(300);  // bricks still arriving are drawn by the view's own timer
    return view->lastFrame();
}

/// What a GUI test case holds: a temporary folder and the main window, its study database and
/// PACS settings in that folder, no saved layout or tools from an earlier run, shown at
/// 1400 x 900 (open() in initTestCase, close() in cleanupTestCase).
struct GuiFixture {
    TempDir dir_;
    std::unique_ptr<ui::MainWindow> window_;

    void open() {
        QSettings().clear();
        window_ = std::make_unique<ui::MainWindow>(QString::fromStdString(dir_.file("db/studies.sqlite")),
                                                   QString::fromStdString(dir_.file("pacs.json")));
        window_->resize(1400, 900);
        window_->show();
        [&] { QVERIFY(QTest::qWaitForWindowExposed(window_.get())); }();
    }
    void close() {
        window_->jobs()->waitIdle(30000);
        window_.reset();
    }
    ui::VolumeView* view() const { return window_->view(); }
    QImage settledFrame() { return test::settledFrame(view()); }
    /// A screenshot of the whole window, kept as an artefact.
    void saveArtifact(const QString& name) { window_->grab().save(guiArtifacts() + "/" + name); }
};

/// A GUI test program's main. HOME and the XDG folders are a temporary folder of this process
/// (tests/support/Hermetic.cpp).
template <class Test>
int runGuiTests(int argc, char** argv) {
    ui::VolumeView::requestGlFormat();
    QApplication app(argc, argv);
    QApplication::setOrganizationName("HolovoxTests");
    Test t;
    return QTest::qExec(&t, argc, argv);
}

}  // namespace hvx::test
