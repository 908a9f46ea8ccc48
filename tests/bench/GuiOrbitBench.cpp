// GUI benchmark (not a test): the workstation's frame time while orbiting, with the frames
// rebuilt from quincunx sub-frames (thesis §3.3) and with whole frames at reduced resolution
// alone, each frame shown compared (PSNR) with the full-quality frame of its camera; and the
// plain cost of full-quality frames through the headless renderer in the same run.
//
//   xvfb-run -a -s "-screen 0 1600x1000x24" build/release/tests/bench/hvx_bench_gui FILE.hvo [--frames 40]
#include <QApplication>
#include <QElapsedTimer>
#include <QTemporaryDir>
#include <QTest>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "render/GpuRayCaster.h"
#include "ui/ImageConversion.h"
#include "ui/MainWindow.h"
#include "ui/TransferFunctionEditor.h"
#include "ui/VolumeView.h"

using namespace hvx;

int main(int argc, char** argv) {
    ui::VolumeView::requestGlFormat();
    // The workstation's settings, job log, caches and database in a folder of the run's own,
    // never the user's (removed at exit).
    QTemporaryDir home;
    if (!home.isValid()) return 1;
    for (const char* var : {"HOME", "XDG_CONFIG_HOME", "XDG_DATA_HOME", "XDG_CACHE_HOME"})
        qputenv(var, (home.path() + "/" + var).toUtf8());
    QApplication app(argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE.hvo [--frames N]\n", argv[0]);
        return 2;
    }
    int frames = 40;
    for (int i = 2; i + 1 < argc; i += 2)
        if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[i + 1]);
    ui::MainWindow window(home.filePath("studies.sqlite"), home.filePath("pacs.json"));
    window.resize(1400, 900);
    window.show();
    if (!QTest::qWaitForWindowExposed(&window) || !window.openOctree(argv[1])) return 1;
    auto* view = window.view();
    const auto start = view->camera();
    struct Orbit {
        double msPerFrame = 0, median = 0, worst = 0, resolution = 0;
        std::vector<core::OrbitCamera> cameras;
        std::vector<QImage> shown;
    };
    // A mouse drag, as a user orbits (2 degrees a frame): the view draws interactive frames
    // while it moves; each frame shown and its camera are kept for the comparison below.
    auto orbit = [&](bool reconstruction) {
        view->setFrameReconstruction(reconstruction);
        view->camera() = start;
        view->update();
        // Settle first (all bricks for the start view), then orbit: one camera step per frame.
        for (int i = 0; i < 400 && !(view->readouts().complete && view->frameCount() > 5); ++i) QTest::qWait(25);
        QTest::qWait(300);
        Orbit o;
        std::vector<double> ms;
        QElapsedTimer total;
        total.start();
        const QPoint c = view->rect().center() - QPoint(frames * 3, 0);
        QTest::mousePress(view, Qt::LeftButton, {}, c);
        for (int f = 0; f < frames; ++f) {
            const int before = view->frameCount();
            QTest::mouseMove(view, c + QPoint(6 * (f + 1), 0));  // 2 degrees at this height
            QElapsedTimer t;
            t.start();
            while (view->frameCount() == before) QCoreApplication::processEvents(QEventLoop::AllEvents, 5);
            ms.push_back(double(t.nsecsElapsed()) / 1e6);
            o.cameras.push_back(view->camera());
            o.shown.push_back(view->lastFrame());
        }
        o.msPerFrame = double(total.nsecsElapsed()) / 1e6 / frames;
        o.resolution = view->readouts().resolution;
        QTest::mouseRelease(view, Qt::LeftButton, {}, c + QPoint(6 * frames, 0));
        std::sort(ms.begin(), ms.end());
        o.median = ms[ms.size() / 2];
        o.worst = ms.back();
        return o;
    };
    const Orbit rebuilt = orbit(true), plainOrbit = orbit(false);
    view->setFrameReconstruction(true);

    // Baseline: the same frames through the headless renderer, working set settled once.
    const auto reader = core::OctreeReader::open(argv[1]);
    core::BrickCache cache(2ull << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSetOptions options;
    options.cpuMirror = false;
    core::WorkingSet ws(*reader, cache, loader, options);
    const auto tf = window.tfEditor()->transferFunction(
        core::OctreeSpace::of(reader->geometry(), reader->brickSize(), reader->levelCount()).minSpacing);
    view->makeCurrent();  // the view's own GL context: the same driver, no Qt drawing
    auto gpuOwner = std::make_unique<render::GpuRayCaster>();
    auto& gpu = *gpuOwner;
    auto cam = start;
    const int w = int(view->width() * view->devicePixelRatioF()), h = int(view->height() * view->devicePixelRatioF());
    ws.converge({cam.view(w, h)}, tf);
    gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, cam.view(w, h));
    QElapsedTimer t;
    t.start();
    for (int f = 0; f < frames; ++f) {
        cam.rotate(view->height() / 90.0, 0, view->height());
        gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, cam.view(w, h));
    }
    const double plain = double(t.nsecsElapsed()) / 1e6 / frames;
    // Each frame shown while moving against the full-quality frame of its camera.
    auto psnr = [&](const Orbit& o) {
        double sum = 0;
        for (std::size_t f = 0; f < o.cameras.size(); ++f) {
            const auto v = o.cameras[f].view(w, h);
            ws.converge({v}, tf);
            const QImage want = ui::toQImage(gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, v));
            const QImage got = o.shown[f].convertToFormat(QImage::Format_RGB32).scaled(want.size());
            double se = 0;
            for (int y = 0; y < want.height(); ++y) {
                const auto* a = reinterpret_cast<const QRgb*>(want.constScanLine(y));
                const auto* b = reinterpret_cast<const QRgb*>(got.constScanLine(y));
                for (int x = 0; x < want.width(); ++x)
                    for (int d : {qRed(a[x]) - qRed(b[x]), qGreen(a[x]) - qGreen(b[x]), qBlue(a[x]) - qBlue(b[x])}) se += double(d * d);
            }
            const double mse = se / (3.0 * want.width() * want.height());
            sum += mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : 99.0;
        }
        return sum / double(o.cameras.size());
    };
    std::setvbuf(stdout, nullptr, _IONBF, 0);
    std::printf("GUI orbit by mouse drag, %d frames of 2 degrees, %dx%d view, %s:\n", frames, view->width(), view->height(),
                reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    for (const auto* o : {&rebuilt, &plainOrbit})
        std::printf("  %-44s %.1f ms/frame (median %.1f, worst %.1f), %.1f fps, resolution x%.2f, %.1f dB against the full frames\n",
                    o == &rebuilt ? "quincunx sub-frames rebuilt:" : "whole frames at reduced resolution (the default):",
                    o->msPerFrame, o->median, o->worst, 1000.0 / o->msPerFrame, o->resolution, psnr(*o));
    std::printf("headless renderer, the same orbit at full quality: %.1f ms/frame\n", plain);
    gpuOwner.reset();
    view->doneCurrent();
    return 0;
}
