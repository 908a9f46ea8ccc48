// GUI tests of the 3D view against the CPU reference under Xvfb (Qt Test): each render mode
// chosen in the Rendering dock (DVR, isosurface, MIP, MinIP, X-ray) draws the frame the CPU
// reference ray caster draws for the same camera, transfer function and settings (the GPU and
// the CPU run separate code for sampling and compositing); MinIP and X-ray frames are grey; and
// the standard-view keys A P L R S I turn the camera so that the edges say what the
// radiological conventions say. A light-field frame rendered on the GUI thread is cancelled by
// its Cancel button in the Jobs panel, while every other click waits. Screenshots under
// <build>/test-artifacts/gui/view-mode-*.png.
#include <QComboBox>
#include <QPushButton>
#include <QSignalSpy>
#include <QTest>
#include <QTimer>

#include <cmath>

#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/CpuRayCaster.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "core/volume/PhantomVoxelSource.h"
#include "tests/gui/GuiTestSupport.h"
#include "ui/JobManager.h"
#include "ui/JobsPanel.h"
#include "ui/LightFieldPanel.h"
#include "ui/ImageConversion.h"
#include "ui/RenderControls.h"
#include "ui/TransferFunctionEditor.h"
#include "ui/VolumeView.h"

using namespace hvx;

namespace {
/// PSNR (dB) of two RGB images of one size; 99 when equal.
double psnr(const QImage& a, const QImage& b) {
    double se = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const QRgb p = a.pixel(x, y), q = b.pixel(x, y);
            for (const int d : {qRed(p) - qRed(q), qGreen(p) - qGreen(q), qBlue(p) - qBlue(q)}) se += double(d) * d;
        }
    const double mse = se / (3.0 * a.width() * a.height()) / (255.0 * 255.0);
    return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0;
}

QString opposite(const QString& label) {
    const QHash<QString, QString> o{{"L", "R"}, {"R", "L"}, {"A", "P"}, {"P", "A"}, {"S", "I"}, {"I", "S"}};
    return o.value(label);
}
}  // namespace

class ViewReferenceTest : public QObject, test::GuiFixture {
    Q_OBJECT

    std::shared_ptr<const core::OctreeReader> reader_;

    /// The CPU reference's frame for the view's camera, transfer function and render settings,
    /// from a working set converged for that view alone.
    QImage reference(const QImage& frame) {
        const auto& g = reader_->geometry();
        const auto space = core::OctreeSpace::of(g, reader_->brickSize(), reader_->levelCount());
        const auto tf = window_->tfEditor()->transferFunction(space.minSpacing);
        const auto settings = window_->renderControls()->settings();
        const auto camera = view()->camera().view(frame.width(), frame.height());
        core::BrickCache cache(std::size_t(512) << 20);
        core::BrickLoader loader(*reader_, cache);
        core::WorkingSetOptions o;
        o.cullByTransferFunction = settings.mode == core::RenderSettings::Mode::Dvr;
        o.isosurface = settings.mode == core::RenderSettings::Mode::Iso;
        o.isoValue = settings.isoValue;
        core::WorkingSet ws(*reader_, cache, loader, o);
        ws.converge({camera}, tf);
        return ui::toQImage(core::CpuRayCaster(*reader_, ws.index(), ws.slotData(), tf, settings).render(camera));
    }

private slots:
    void initTestCase() {
        open();
        core::PhantomVoxelSource phantom({96, 96, 64}, 7);
        core::JobContext job;
        core::OctreeBuilder(core::BuildOptions{}).build(phantom, dir_.file("phantom.hvo"), job);
        QVERIFY(window_->openOctree(QString::fromStdString(dir_.file("phantom.hvo"))));
        reader_ = core::OctreeReader::open(dir_.file("phantom.hvo"));
        window_->view()->setStandardView(core::OrbitCamera::Standard::Anterior);
    }

    void everyModeDrawsTheCpuReferencesFrame() {
        const QStringList names{"dvr", "iso", "mip", "minip", "xray"};
        for (int mode = 0; mode < 5; ++mode) {
            window_->renderControls()->mode()->setCurrentIndex(mode);
            const QImage frame = settledFrame().convertToFormat(QImage::Format_RGB32);
            const QImage want = reference(frame);
            QCOMPARE(want.size(), frame.size());
            const double db = psnr(frame, want);
            frame.save(test::guiArtifacts() + "/view-mode-" + names[mode] + ".png");
            qInfo("%s: the 3D view's frame vs the CPU reference, %.1f dB", qPrintable(names[mode]), db);
            // llvmpipe and the CPU reference agree at 84.7-96.9 dB here (filtering and float
            // order differ in the last bits): 80 dB leaves a margin; a wrong mode, camera,
            // window or transfer function falls far below.
            QVERIFY2(db > 80.0, qPrintable(QString("%1: %2 dB").arg(names[mode]).arg(db)));
            int lit = 0;
            for (int y = 0; y < frame.height(); y += 4)
                for (int x = 0; x < frame.width(); x += 4) {
                    const QRgb p = frame.pixel(x, y);
                    lit += qRed(p) + qGreen(p) + qBlue(p) > 30 ? 1 : 0;
                    if (mode >= 2) QVERIFY2(qRed(p) == qGreen(p) && qGreen(p) == qBlue(p), "a projection is grey");
                }
            QVERIFY2(lit > 100, qPrintable(names[mode] + " draws nothing"));
        }
        window_->renderControls()->mode()->setCurrentIndex(0);
    }

    void standardViewKeysTurnTheCamera() {
        struct Expect {
            Qt::Key key;
            const char *right, *up;
        };
        auto* v = view();
        v->setFocus();
        for (const auto& e : {Expect{Qt::Key_A, "L", "S"}, Expect{Qt::Key_P, "R", "S"}, Expect{Qt::Key_L, "P", "S"},
                              Expect{Qt::Key_R, "A", "S"}, Expect{Qt::Key_S, "R", "A"}, Expect{Qt::Key_I, "L", "A"}}) {
            QTest::keyClick(v, e.key);
            const QStringList labels = v->orientationLabels();  // left, right, top, bottom
            const QStringList want{opposite(e.right), e.right, e.up, opposite(e.up)};
            QCOMPARE(labels, want);
        }
    }

    void aLightFieldFrameIsCancelledFromTheJobsPanel() {
        auto* lf = window_->lightField();
        auto* render = lf->findChild<QPushButton*>("lightFieldRender");
        QVERIFY(render);
        int frameJob = -1, startedJobs = 0;
        bool clicked = false;
        QSignalSpy finished(window_->jobs(), &ui::JobManager::finished);
        connect(window_->jobs(), &ui::JobManager::started, this, [&](int id, const QString& title) {
            ++startedJobs;
            if (title.startsWith("Light-field frame")) frameJob = id;
        });
        // At its first progress report, while it runs: the Render button again (must wait),
        // then the job's own Cancel button in the Jobs panel.
        connect(window_->jobs(), &ui::JobManager::progressed, this, [&](int id, double, double, const QString&) {
            if (id != frameJob || clicked) return;
            clicked = true;
            QTimer::singleShot(0, this, [&, id] {
                QTest::mouseClick(render, Qt::LeftButton);
                auto* cancel = window_->jobsPanel()->findChild<QPushButton*>(QStringLiteral("cancelJob%1").arg(id));
                QVERIFY(cancel);
                QTest::mouseClick(cancel, Qt::LeftButton);
            });
        });
        QTest::mouseClick(render, Qt::LeftButton);
        QTRY_VERIFY_WITH_TIMEOUT(frameJob > 0 && clicked, 30000);
        bool cancelled = false;
        for (const auto& f : finished)
            if (f.at(0).toInt() == frameJob) cancelled = f.at(1).toString() == "cancelled";
        QVERIFY2(cancelled, "the light-field frame was not cancelled by its Cancel button");
        QCOMPARE(startedJobs, 1);  // the click on Render while it ran did not start another
        disconnect(window_->jobs(), nullptr, this, nullptr);
    }

    void cleanupTestCase() { close(); }
};

int main(int argc, char** argv) { return test::runGuiTests<ViewReferenceTest>(argc, argv); }

#include "ViewReferenceTest.moc"
