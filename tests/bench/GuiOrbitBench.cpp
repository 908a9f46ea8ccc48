// GUI benchmark (not a test): the workstation's frame time while orbiting, against the plain
// cost of the same frames through the headless renderer (EGL, no Qt) in the same run, so the
// ratio shows what the GUI adds (working-set refinement per frame, readback, drawing, overlays).
//
//   xvfb-run -a -s "-screen 0 1600x1000x24" build/release/tests/bench/hvx_bench_gui FILE.hvo [--frames 40]
#include <QApplication>
#include <QElapsedTimer>
#include <QTest>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "render/GpuRayCaster.h"
#include "ui/MainWindow.h"
#include "ui/TransferFunctionEditor.h"
#include "ui/VolumeView.h"

using namespace hvx;

int main(int argc, char** argv) {
    ui::VolumeView::requestGlFormat();
    qputenv("XDG_CONFIG_HOME", "/tmp/hvx-bench-gui-config");
    QApplication app(argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE.hvo [--frames N]\n", argv[0]);
        return 2;
    }
    int frames = 40;
    for (int i = 2; i + 1 < argc; i += 2)
        if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[i + 1]);
    ui::MainWindow window("/tmp/hvx-bench-gui.sqlite", "/tmp/hvx-bench-gui-pacs.json");
    window.resize(1400, 900);
    window.show();
    if (!QTest::qWaitForWindowExposed(&window) || !window.openOctree(argv[1])) return 1;
    auto* view = window.view();
    // Settle first (all bricks for the start view), then orbit: one camera step per frame.
    for (int i = 0; i < 400 && !(view->readouts().complete && view->frameCount() > 5); ++i) QTest::qWait(25);
    std::vector<double> ms;
    QElapsedTimer total;
    total.start();
    // A mouse drag, as a user orbits: the view draws interactive-quality frames while it moves.
    const QPoint c = view->rect().center() - QPoint(frames * 3, 0);
    QTest::mousePress(view, Qt::LeftButton, {}, c);
    for (int f = 0; f < frames; ++f) {
        const int before = view->frameCount();
        QTest::mouseMove(view, c + QPoint(6 * (f + 1), 0));  // 2 degrees at this height
        QElapsedTimer t;
        t.start();
        while (view->frameCount() == before) QCoreApplication::processEvents(QEventLoop::AllEvents, 5);
        ms.push_back(double(t.nsecsElapsed()) / 1e6);
    }
    const double gui = double(total.nsecsElapsed()) / 1e6 / frames;
    const double resolution = view->readouts().resolution;
    QTest::mouseRelease(view, Qt::LeftButton, {}, c + QPoint(6 * frames, 0));
    std::sort(ms.begin(), ms.end());
    std::setvbuf(stdout, nullptr, _IONBF, 0);
    std::printf("GUI orbit by mouse drag, %dx%d view: %.1f ms/frame (median %.1f, worst %.1f), %.1f fps, drawn at "
                "resolution x%.2f while moving\n", view->width(), view->height(), gui, ms[ms.size() / 2], ms.back(),
                1000.0 / gui, resolution);

    // Baseline: the same frames through the headless renderer, working set settled once.
    const auto reader = core::OctreeReader::open(argv[1]);
    core::BrickCache cache(2ull << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSetOptions options;
    options.cpuMirror = false;
    core::WorkingSet ws(*reader, cache, loader, options);
    const auto tf = window.tfEditor()->transferFunction(
        core::OctreeSpace::of(reader->geometry(), reader->brickSize(), reader->levelCount()).minSpacing);
    const auto start = view->camera();
    view->makeCurrent();  // the view's own GL context: the same driver, no Qt drawing
    auto gpuOwner = std::make_unique<render::GpuRayCaster>();
    auto& gpu = *gpuOwner;
    auto cam = start;
    ws.converge({cam.view(view->width(), view->height())}, tf);
    gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, cam.view(view->width(), view->height()));
    QElapsedTimer t;
    t.start();
    for (int f = 0; f < frames; ++f) {
        cam.rotate(view->height() / 90.0, 0, view->height());
        gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, cam.view(view->width(), view->height()));
    }
    const double plain = double(t.nsecsElapsed()) / 1e6 / frames;
    std::printf("headless renderer, same frames at full quality: %.1f ms/frame; GUI / headless = %.2f\n", plain,
                gui / plain);
    gpuOwner.reset();
    view->doneCurrent();
    return 0;
}
