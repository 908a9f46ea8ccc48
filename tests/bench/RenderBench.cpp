// Rendering benchmark (not a test): Holovox's GPU ray caster (EGL) and CPU reference against
// VTK's vtkGPUVolumeRayCastMapper and vtkFixedPointVolumeRayCastMapper, in one run, with the
// same volume, transfer function control points, camera and image size. VTK needs an X display
// (run under xvfb-run); Holovox renders headless.
//
//   xvfb-run -a build/release/tests/bench/hvx_bench_render INPUT [--size 512|WxH] [--frames 8] [--rounds 3]
//                                                           [--breakdown]
//   Rounds alternate Holovox and VTK over the same frames; the ratio reported is the median
//   of the rounds' ratios. --breakdown times the GPU frame with parts switched off.
//   INPUT: a volume file or phantom:XxYxZ (loaded whole for VTK; Holovox streams its octree),
//          or an existing FILE.hvo larger than RAM: Holovox alone, within its memory budget
//          (VTK must hold the whole volume, and cannot).
#include <vtkColorTransferFunction.h>
#include <vtkFixedPointVolumeRayCastMapper.h>
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPiecewiseFunction.h>
#include <vtkPointData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkCamera.h>
#include <vtkShortArray.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>
#include <vtkMatrix4x4.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>

#include <sys/resource.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/reference/CpuRayCaster.h"
#include "core/camera/InteractiveQuality.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/VoxelSourceFactory.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"

using namespace hvx;
using Clock = std::chrono::steady_clock;

namespace {
double seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }
/// User and system CPU time of the whole process (all driver threads), in seconds.
double cpuSeconds() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s INPUT [--size N|WxH] [--frames N] [--rounds N] [--tf PRESET] [--breakdown]\n",
                     argv[0]);
        return 2;
    }
    int width = 512, height = 512, frames = 8;
    std::string preset = "ct-bone";
    int rounds = 3;
    bool breakdown = false;
    for (int i = 2; i < argc; ++i)
        if (!std::strcmp(argv[i], "--breakdown")) breakdown = true;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--rounds")) rounds = std::max(1, std::stoi(argv[i + 1]));
        if (!std::strcmp(argv[i], "--size")) {  // N (square) or WxH, e.g. 1920x1080
            const std::string v = argv[i + 1];
            const auto x = v.find('x');
            width = std::stoi(v.substr(0, x));
            height = x == std::string::npos ? width : std::stoi(v.substr(x + 1));
        } else if (!std::strcmp(argv[i], "--frames"))
            frames = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--tf")) preset = argv[i + 1];
    }
    const bool octreeOnly = std::string(argv[1]).ends_with(".hvo");
    std::unique_ptr<core::VoxelSource> source;
    std::string hvo = argv[1];
    if (!octreeOnly) {
        source = core::VoxelSourceFactory::open(argv[1]);
        hvo = (std::filesystem::temp_directory_path() / "hvx-bench-render.hvo").string();
        core::JobContext job;
        core::OctreeBuilder(core::BuildOptions{}).build(*source, hvo, job);
    }
    const auto reader = core::OctreeReader::open(hvo);
    const auto& g = reader->geometry();
    const auto g0 = g;
    if (g0.modality != "CT" && preset == "ct-bone") preset = "mr-default";
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    const auto tf = core::TransferFunction::preset(preset, g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                                   space.minSpacing);
    const glm::dvec3 centre = space.centre();
    const glm::dvec3 corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const double radius = glm::length(centre - corner) / std::tan(glm::radians(15.0)) * 1.05;
    auto viewAt = [&](int f) { return core::View::orbit(centre, radius, 30.0 + 10.0 * f, 15.0, width, height); };

    // Holovox: working set for the first view (all views see the whole volume), then frames.
    core::BrickCache cache(octreeOnly ? 1ull << 30 : 4ull << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSetOptions options;
    options.cpuMirror = !octreeOnly;
    core::WorkingSet ws(*reader, cache, loader, options);
    ws.converge({viewAt(0)}, tf);
    render::EglOffscreenContext ctx;
    auto gpuOwner = std::make_unique<render::GpuRayCaster>();  // released before VTK's windows go
    auto& gpu = *gpuOwner;
    gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, viewAt(0));  // compile + upload
    auto timeHolovoxGpu = [&] {
        ctx.makeCurrent();  // VTK's window takes the thread's context between rounds
        const auto t = Clock::now();
        for (int f = 1; f <= frames; ++f) gpu.render(*reader, ws.index(), ws.slotBricks(), tf, {}, viewAt(f));
        const double ms = seconds(t) * 1000.0 / frames;
        ctx.release();
        return ms;
    };
    const double gpuMs = timeHolovoxGpu();
    ctx.makeCurrent();
    std::printf("Holovox GPU ray caster (%s): %.1f ms/frame (pool %.0f MiB)\n", ctx.info().renderer.c_str(), gpuMs,
                double(gpu.poolBytes()) / double(1 << 20));
    {
        // While the camera moves: reduced resolution and doubled step, sized to 40 ms frames.
        core::InteractiveQuality quality;
        quality.frameDone({}, gpuMs);
        const auto level = quality.next(true);
        core::RenderSettings moving;
        moving.stepScale = level.stepScale;
        const auto tm = Clock::now();
        for (int f = 1; f <= frames; ++f)
            gpu.render(*reader, ws.index(), ws.slotBricks(), tf, moving, viewAt(f).scaled(level.resolution));
        std::printf("Holovox GPU while moving: %.1f ms/frame (resolution x%.2f, step x%.0f)\n",
                    seconds(tm) * 1000.0 / frames, level.resolution, level.stepScale);
        if (breakdown) {  // where the frame time goes: the same frames with parts switched off
            auto time = [&](const char* what, const core::TransferFunction& t, const core::RenderSettings& s,
                            double scale = 1.0) {
                // The best of three passes (this VM's timings are noisy), in wall time and in
                // the process's CPU time (which excludes time stolen by other guests).
                double best = 1e30, bestCpu = 1e30;
                for (int pass = 0; pass < 3; ++pass) {
                    const double c0 = cpuSeconds();
                    const auto tb = Clock::now();
                    for (int f = 1; f <= frames; ++f)
                        gpu.render(*reader, ws.index(), ws.slotBricks(), t, s, viewAt(f).scaled(scale));
                    best = std::min(best, seconds(tb) * 1000.0 / frames);
                    bestCpu = std::min(bestCpu, (cpuSeconds() - c0) * 1000.0 / frames);
                }
                std::printf("  breakdown: %-40s %6.1f ms/frame, CPU %6.1f ms/frame\n", what, best, bestCpu);
            };
            time("full (DVR, shaded)", tf, {});
            core::RenderSettings flat;
            flat.shading = false;
            time("no shading (no gradients)", tf, flat);
            core::RenderSettings mip;
            mip.mode = core::RenderSettings::Mode::Mip;
            time("MIP (every sample, no TF)", tf, mip);
            mip.stepScale = 8.0;
            time("MIP, step x8 (mostly per-leaf costs)", tf, mip);
            const core::TransferFunction clear({{g.valueMin, {0, 0, 0, 0}}, {g.valueMax, {0, 0, 0, 0}}}, g.valueMin,
                                               g.valueMax, tf.referenceLength());
            time("transparent TF (march, TF lookups)", clear, flat);
            time("8x8 image (uploads, fixed costs)", tf, {}, 8.0 / height);
            // The flexible ray caster's features (thesis §3.2.2-3.3), each against "full" above.
            auto faded = tf;  // gradient opacity: a ramp from 0.5% to 2% of the value range per mm
            const double range = g.valueMax - g.valueMin;
            faded.setGradientOpacity({{0.005 * range, 0.0}, {0.02 * range, 1.0}});
            time("gradient opacity", faded, {});
            core::RenderSettings detail;
            detail.normalUnsharp = 2.0;
            time("normal unsharp masking (k 2)", tf, detail);
            detail.normalUnsharp = 0.0;
            detail.exaggeratedShading = 1.0;
            time("exaggerated shading", tf, detail);
            // Refraction (the refract stepper): bending nothing (an index ≠ 1 only at the top value)
            // and with what shows refracting at 1.3. The cut is the one above (the transfer
            // function's visible bricks: by opacity, no refracting brick is transparent).
            auto straight = tf;
            straight.setRefraction({{g.valueMax - 0.02 * range, 1.0}, {g.valueMax, 1.5}});
            time("refract stepper, bending nothing", straight, {});
            auto bent = tf;
            bent.setRefraction(tf.refractionByOpacity(1.3));
            time("refraction (what shows at index 1.3)", bent, {});
            // Multilevel sampling: the leaves where the level field is coarser also read their ancestors.
            std::size_t blending = 0, bricks = 0;
            for (std::size_t i = 0; i < ws.index().levels.size(); ++i) {
                blending += ws.index().levels[i].blends;
                bricks += (ws.index().nodes[i].y & core::SpatialIndex::kLeafBit) && ws.index().nodes[i].x != core::SpatialIndex::kNone;
            }
            std::printf("  breakdown: multilevel sampling: %zu of %zu leaves with a brick blend with coarser levels (levels %d-%d)\n",
                        blending, bricks, ws.stats().finestLevel, ws.stats().coarsestLevel);
            core::RenderSettings levels;
            levels.multilevel = true;
            time("multilevel sampling", tf, levels);
            core::RenderSettings quincunx;
            quincunx.subFrame = 1;
            time("one quincunx sub-frame (a quarter of the rays)", tf, quincunx);
        }
        ctx.release();
    }
    if (octreeOnly) {
        rusage ru{};
        getrusage(RUSAGE_SELF, &ru);
        std::printf(
            "%s: %ux%ux%u (%.1f GiB of voxels): Holovox GPU %.1f ms/frame at %dx%d, peak RSS %.0f MiB; VTK "
            "would have to hold all %.1f GiB (as float: %.1f GiB) in RAM\n",
            argv[1], g.dims[0], g.dims[1], g.dims[2], double(g.byteSize()) / double(1ull << 30), gpuMs, width, height,
            double(ru.ru_maxrss) / 1024.0, double(g.byteSize()) / double(1ull << 30),
            double(g.voxelCount()) * 4.0 / double(1ull << 30));
        ctx.makeCurrent();  // for the caster's GL objects to go
        return 0;
    }
    const core::CpuRayCaster cpu(*reader, ws.index(), ws.slotData(), tf, {});
    auto timeHolovoxCpu = [&] {
        const auto t = Clock::now();
        for (int f = 1; f <= frames; ++f) cpu.render(viewAt(f));
        return seconds(t) * 1000.0 / frames;
    };

    // VTK: the whole volume in memory, physical values, same TF points, same camera.
    vtkNew<vtkImageData> image;
    image->SetDimensions(int(g0.dims[0]), int(g0.dims[1]), int(g0.dims[2]));
    image->SetSpacing(g0.spacing.x, g0.spacing.y, g0.spacing.z);
    image->SetOrigin(0, 0, 0);
    image->AllocateScalars(VTK_FLOAT, 1);
    {
        const std::size_t slice = std::size_t(g0.dims[0]) * g0.dims[1];
        std::vector<char> buf(slice * core::scalarSize(g0.scalarType));
        auto* out = static_cast<float*>(image->GetScalarPointer());
        for (std::uint32_t z = 0; z < g0.dims[2]; ++z) {
            source->readSlices(z, 1, buf.data());
            core::dispatchScalar(g0.scalarType, [&](auto tag) {
                using T = decltype(tag);
                const T* in = reinterpret_cast<const T*>(buf.data());
                for (std::size_t i = 0; i < slice; ++i) out[z * slice + i] = float(in[i]);
            });
        }
    }
    vtkNew<vtkMatrix4x4> placement;  // direction cosines and origin: VTK applies the spacing itself
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) placement->SetElement(r, c, g0.direction[c][r]);
        placement->SetElement(r, 3, g0.origin[r]);
    }
    vtkNew<vtkColorTransferFunction> colours;
    vtkNew<vtkPiecewiseFunction> opacity;
    for (const auto& p : tf.points()) {
        colours->AddRGBPoint(p.value, p.rgba.r, p.rgba.g, p.rgba.b);
        opacity->AddPoint(p.value, p.rgba.a);
    }
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(colours);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(tf.referenceLength());
    property->SetInterpolationTypeToLinear();
    property->ShadeOn();
    property->SetAmbient(0.35);
    property->SetDiffuse(0.65);
    property->SetSpecular(0.25);
    property->SetSpecularPower(24.0);
    // One window per VTK mapper, kept for all rounds.
    struct VtkRun {
        vtkNew<vtkVolume> volume;
        vtkNew<vtkRenderer> renderer;
        vtkNew<vtkRenderWindow> window;
    };
    auto setUp = [&](VtkRun& run, vtkVolumeMapper* mapper) {
        mapper->SetInputData(image);
        run.volume->SetMapper(mapper);
        run.volume->SetProperty(property);
        run.volume->SetUserMatrix(placement);
        run.renderer->AddVolume(run.volume);
        run.renderer->SetBackground(0, 0, 0);
        run.window->SetOffScreenRendering(1);
        run.window->SetSize(width, height);
        run.window->AddRenderer(run.renderer);
    };
    auto timeVtk = [&](VtkRun& run, int first, int last) {
        const auto t = Clock::now();
        for (int f = first; f <= last; ++f) {
            const auto v = viewAt(f);
            vtkCamera* cam = run.renderer->GetActiveCamera();
            cam->SetPosition(v.eye.x, v.eye.y, v.eye.z);
            cam->SetFocalPoint(v.target.x, v.target.y, v.target.z);
            cam->SetViewUp(v.up.x, v.up.y, v.up.z);
            cam->SetViewAngle(v.fovYDegrees);
            run.renderer->ResetCameraClippingRange();
            run.window->Render();
        }
        const double ms = seconds(t) * 1000.0 / (last - first + 1);
        run.window->ReleaseCurrent();  // libglvnd allows one API's context per thread at a time
        return ms;
    };
    const float sampleDistance = float(std::min({g0.spacing.x, g0.spacing.y, g0.spacing.z}));
    vtkNew<vtkGPUVolumeRayCastMapper> vtkGpu;
    vtkGpu->SetAutoAdjustSampleDistances(0);
    vtkGpu->SetSampleDistance(sampleDistance);
    vtkNew<vtkFixedPointVolumeRayCastMapper> vtkCpu;
    vtkCpu->SetAutoAdjustSampleDistances(0);
    vtkCpu->SetSampleDistance(sampleDistance);
    VtkRun gpuRun, cpuRun;
    setUp(gpuRun, vtkGpu);
    setUp(cpuRun, vtkCpu);
    timeVtk(gpuRun, 0, 0);  // uploads
    timeVtk(cpuRun, 0, 0);

    // Rounds that alternate the four renderers over the same frames, so that each ratio is
    // taken between timings a few seconds apart: this VM's speed drifts by ±15% over a run.
    std::vector<double> gpuRatios, cpuRatios;
    for (int r = 1; r <= rounds; ++r) {
        const double hg = timeHolovoxGpu(), vg = timeVtk(gpuRun, 1, frames);
        const double hc = timeHolovoxCpu(), vc = timeVtk(cpuRun, 1, frames);
        std::printf(
            "round %d: Holovox GPU %.1f ms, VTK vtkGPUVolumeRayCastMapper %.1f ms (%.2f); Holovox CPU %.1f ms, "
            "VTK vtkFixedPointVolumeRayCastMapper %.1f ms (%.2f)\n",
            r, hg, vg, hg / vg, hc, vc, hc / vc);
        gpuRatios.push_back(hg / vg);
        cpuRatios.push_back(hc / vc);
    }
    auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    };
    std::printf(
        "%s %ux%ux%u, %dx%d, %d frames x %d rounds: Holovox GPU / VTK GPU = %.2f (median; range %.2f-%.2f; "
        "target <= 0.5), Holovox CPU / VTK fixed-point = %.2f (range %.2f-%.2f)\n",
        argv[1], g0.dims[0], g0.dims[1], g0.dims[2], width, height, frames, rounds, median(gpuRatios),
        *std::min_element(gpuRatios.begin(), gpuRatios.end()), *std::max_element(gpuRatios.begin(), gpuRatios.end()),
        median(cpuRatios), *std::min_element(cpuRatios.begin(), cpuRatios.end()),
        *std::max_element(cpuRatios.begin(), cpuRatios.end()));
    ctx.makeCurrent();
    gpuOwner.reset();
    ctx.release();
    std::filesystem::remove(hvo);
    return 0;
}
