// Split-voxel benchmark (not a test): against plain octrees in the same run, on the CT phantom,
// the MRI template and a label map (JHU white-matter atlas), CPU reference renders:
// build time (next to the plain cost of reading the input), size on disk, frame time at full
// and at coarse accuracy, and PSNR against the full-resolution trilinear render at the same
// element count (a plain level of 2^L voxels against split cells of 2^L voxels). The plain
// octree is drawn as the product draws it: trilinear for intensities, nearest labels for a label map.
// Then the GPU ray caster's frame times (EGL, whatever GPU the machine has) for the plain octree
// and the split-voxel octree at each of the same levels (median of 3 frames after a warm one).
//
//   build/release/tests/bench/hvx_bench_splitvoxels [--size 384] [--phantom 256x256x256] [--png DIR]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <glm/trigonometric.hpp>
#include <unistd.h>

#include "core/appearance/LabelTable.h"
#include "core/image/ImageWriter.h"
#include "core/octree/OctreeBuilder.h"
#include "core/octree/OctreeReader.h"
#include "core/octree/SplitVoxelGrid.h"
#include "core/octree/SplitVoxelOctreeBuilder.h"
#include "core/reference/CpuRayCaster.h"
#include "core/reference/SplitVoxelRayCaster.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/volume/VoxelSourceFactory.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"

using namespace hvx;
using Clock = std::chrono::steady_clock;

namespace {
double seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

double psnr(const core::RenderImage& a, const core::RenderImage& b) {
    double se = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = double(std::clamp(a.rgba[i][c], 0.0f, 1.0f)) - double(std::clamp(b.rgba[i][c], 0.0f, 1.0f));
            se += d * d;
        }
    const double mse = se / (3.0 * double(a.rgba.size()));
    return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0;
}

/// The plain octree's render with its cut's finest level at `targetLevel` (0: full resolution):
/// the accuracy target is raised until the cut is that coarse.
core::RenderImage plain(const core::OctreeReader& reader, const core::View& view, const core::TransferFunction& tf,
                        int targetLevel, int& level, double& ms) {
    core::BrickCache cache(std::size_t(4) << 30);
    core::BrickLoader loader(reader, cache);
    std::unique_ptr<core::WorkingSet> ws;
    for (double vpp = targetLevel == 0 ? 1e-6 : 0.5;; vpp *= 1.25) {
        core::WorkingSetOptions o;
        o.voxelsPerPixel = vpp;
        o.maxBricks = 1u << 16;
        ws = std::make_unique<core::WorkingSet>(reader, cache, loader, o);
        ws->converge({view}, tf);
        if (ws->stats().finestLevel >= targetLevel || vpp > 1e6) break;
    }
    level = ws->stats().finestLevel;
    core::RenderSettings rs;
    const core::CpuRayCaster caster(reader, ws->index(), ws->slotData(), tf, rs);
    const auto t = Clock::now();
    auto img = caster.render(view);
    ms = seconds(t) * 1000.0;
    return img;
}

std::string g_png;  // --png DIR: the renders, to look at
std::unique_ptr<render::EglOffscreenContext> g_gl;  // null when no GL 4.5 context could be made
std::unique_ptr<render::GpuRayCaster> g_gpu;

/// The GPU's frame time (ms, median of 3 after a warm frame) for `reader` at its level `level`
/// wherever the view reaches it.
double gpuFrameMs(const core::OctreeReader& reader, int level, const core::View& view, const core::TransferFunction& tf) {
    core::BrickCache cache(std::size_t(4) << 30);
    core::BrickLoader loader(reader, cache);
    core::WorkingSetOptions o;
    o.voxelsPerPixel = 1e-6;
    o.finestLevel = level;
    o.maxBricks = 1u << 16;
    o.cpuMirror = false;
    core::WorkingSet ws(reader, cache, loader, o);
    ws.converge({view}, tf);
    core::RenderSettings rs;
    std::vector<double> ms;
    for (int i = 0; i < 4; ++i) {
        const auto t = Clock::now();
        g_gpu->render(reader, ws.index(), ws.slotBricks(), tf, rs, view);
        if (i) ms.push_back(seconds(t) * 1000.0);
    }
    std::sort(ms.begin(), ms.end());
    return ms[1];
}

void run(const std::string& name, core::VoxelSource& source, bool labels, int size, const std::filesystem::path& dir) {
    const auto& g = source.geometry();
    std::printf("\n%s: %ux%ux%u %s%s\n", name.c_str(), g.dims[0], g.dims[1], g.dims[2],
                std::string(core::scalarName(g.scalarType)).c_str(), labels ? " labels" : "");
    // Baseline: the plain cost of reading the input.
    auto t = Clock::now();
    {
        std::vector<std::uint8_t> slab(std::size_t(g.dims[0]) * g.dims[1] * core::scalarSize(g.scalarType) * 16);
        for (std::uint32_t z = 0; z < g.dims[2]; z += 16) source.readSlices(z, std::min<std::uint32_t>(16, g.dims[2] - z), slab.data());
    }
    const double read = seconds(t);
    core::BuildOptions b;
    b.labels = labels;
    core::JobContext job;
    const auto plainPath = (dir / (name + ".hvo")).string(), splitPath = (dir / (name + "-split.hvo")).string();
    t = Clock::now();
    const auto pr = core::OctreeBuilder(b).build(source, plainPath, job);
    const double plainBuild = seconds(t);
    core::SplitVoxelOptions so;
    so.labels = labels;
    t = Clock::now();
    const auto sr = core::SplitVoxelOctreeBuilder(b, so).build(source, splitPath, job);
    const double splitBuild = seconds(t);
    std::printf("  build  read input %.2f s | plain %.2f s, %.1f MiB | split-voxels %.2f s, %.1f MiB (%.2f x plain)\n", read,
                plainBuild, double(pr.fileBytes) / 1048576.0, splitBuild, double(sr.fileBytes) / 1048576.0,
                double(sr.fileBytes) / double(pr.fileBytes));

    // The same levels in memory for the split renders.
    std::vector<core::SplitVoxelGrid> levels{core::SplitVoxelGrid::build(source, so, job)};
    for (int l = 1; l < 4; ++l) levels.push_back(levels.back().coarser(so, job));
    const auto reader = core::OctreeReader::open(plainPath);
    const auto space = core::OctreeSpace::of(reader->geometry(), reader->brickSize(), reader->levelCount());
    const auto& r = reader->geometry();  // the value range as the build found it (a NIfTI does not say)
    const glm::dvec3 centre = space.centre(), corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const auto view = core::View::orbit(centre, glm::length(centre - corner) / std::tan(glm::radians(15.0)) * 1.05, 30, 15,
                                        size, size);
    const auto tf = labels ? [&] {
        std::set<int> seen;
        for (const auto& l : {levels[0]})
            for (std::uint32_t z = 0; z < l.dims()[2]; ++z)
                for (std::uint32_t y = 0; y < l.dims()[1]; ++y)
                    for (std::uint32_t x = 0; x < l.dims()[0]; ++x) seen.insert(int(l.at(x, y, z).front));
        seen.erase(0);
        return core::TransferFunction::forLabels(core::LabelTable::generated({seen.begin(), seen.end()}), 1.0, space.minSpacing);
    }()
                           : g.modality == "CT"
                               ? core::TransferFunction::preset("ct-bone", r.valueMin, r.valueMax, r.rescaleSlope,
                                                                r.rescaleIntercept, space.minSpacing)
                               // The MRI template: background and CSF clear, the brain's tissue from
                               // 40% of the range up.
                               : core::TransferFunction({{r.valueMin + 0.4 * (r.valueMax - r.valueMin), {0.9, 0.8, 0.7, 0.0}},
                                                         {r.valueMin + 0.7 * (r.valueMax - r.valueMin), {1.0, 0.9, 0.8, 0.6}},
                                                         {r.valueMax, {1.0, 1.0, 1.0, 0.9}}},
                                                        r.valueMin, r.valueMax, space.minSpacing);
    int level = -1;
    double fullMs = 0;
    const auto full = plain(*reader, view, tf, 0, level, fullMs);
    core::RenderSettings rs;
    core::VolumeGeometry labelled = g;  // labels are classified by their own entry, as the plain caster does
    labelled.isLabel = labels;
    for (int l = 0; l < 4; ++l) {
        const std::uint32_t cell = levels[std::size_t(l)].cellVoxels();
        int pl = -1;
        double plainMs = 0;
        const auto coarse = plain(*reader, view, tf, int(std::log2(double(cell)) + 0.5), pl, plainMs);
        const auto ts = Clock::now();
        const auto split = core::SplitVoxelRayCaster(levels[std::size_t(l)], labelled, tf, rs).render(view);
        const double splitMs = seconds(ts) * 1000.0;
        if (!g_png.empty()) {
            const std::string base = g_png + "/" + name + "-cells" + std::to_string(cell);
            core::ImageWriter::writePng(coarse, base + "-trilinear.png");
            core::ImageWriter::writePng(split, base + "-split.png");
            if (l == 0) core::ImageWriter::writePng(full, g_png + "/" + name + "-full.png");
        }
        std::printf("  cells of %2u voxels | plain, cut's finest level %d: %6.0f ms, %5.1f dB | split-voxels: %6.0f ms, "
                    "%5.1f dB (full resolution: level %d, %.0f ms)\n",
                    cell, pl, plainMs, psnr(coarse, full), splitMs, psnr(split, full), level, fullMs);
    }
    if (!g_gpu) return;
    const auto splitReader = core::OctreeReader::open(splitPath, true);
    std::printf("  GPU frames (%s):", g_gl->info().renderer.c_str());
    std::printf(" full resolution %.0f ms |", gpuFrameMs(*reader, 0, view, tf));
    for (int l = 0; l < std::min(4, splitReader->levelCount()); ++l) {
        const std::uint32_t cell = levels[std::size_t(l)].cellVoxels();
        const int pl = int(std::log2(double(cell)) + 0.5);
        if (pl >= reader->levelCount()) break;
        std::printf(" cells of %u: plain %.0f / split %.0f ms |", cell, gpuFrameMs(*reader, pl, view, tf),
                    gpuFrameMs(*splitReader, l, view, tf));
    }
    std::printf("\n");
}
}  // namespace

int main(int argc, char** argv) {
    int size = 384;
    std::array<std::uint32_t, 3> dims{256, 256, 256};
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size")) size = std::max(64, std::atoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--phantom")) dims = core::VoxelSourceFactory::parseDims(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--png")) g_png = argv[i + 1];
    }
    const auto dir = std::filesystem::temp_directory_path() / ("hvx-split-bench-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::printf("CPU reference renders, %dx%d, ThreadPool of the machine's cores\n", size, size);
    try {
        g_gl = std::make_unique<render::EglOffscreenContext>();
        g_gpu = std::make_unique<render::GpuRayCaster>();
    } catch (const std::exception& e) {
        std::printf("no GPU frame times: %s\n", e.what());
        g_gpu.reset();
        g_gl.reset();
    }
    {
        core::PhantomVoxelSource ct(dims, 1);
        run("ct-phantom", ct, false, size, dir);
    }
    for (const auto& [name, path, labels] :
         {std::tuple<std::string, std::string, bool>{"mri-template", "/usr/share/mricron/templates/ch2better.nii.gz", false},
          {"jhu-labels", "/usr/share/mricron/templates/JHU-WhiteMatter-labels-1mm.nii.gz", true}}) {
        if (!std::filesystem::exists(path)) {
            std::printf("\n%s: %s is missing (Debian's mricron-data)\n", name.c_str(), path.c_str());
            return 1;
        }
        auto source = core::VoxelSourceFactory::open(path);
        run(name, *source, labels, size, dir);
    }
    std::filesystem::remove_all(dir);
    return 0;
}
