// Tools benchmark (not a test): the frame-time cost of each illustrative tool, and of three
// together, against no tool, in the same run (GPU ray caster through EGL; the thesis reports
// about 10%).
//
//   build/release/tests/bench/hvx_bench_tools FILE.hvo [--size 512] [--frames 4]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"

using namespace hvx;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE.hvo [--size N] [--frames N]\n", argv[0]);
        return 2;
    }
    int size = 512, frames = 4;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size")) size = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[i + 1]);
    }
    const auto reader = core::OctreeReader::open(argv[1]);
    const auto& g = reader->geometry();
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    const glm::dvec3 centre = space.centre();
    const glm::dvec3 corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const double radius = glm::length(centre - corner);
    const auto view = core::View::orbit(centre, radius / std::tan(glm::radians(15.0)) * 1.05, 30, 15, size, size);
    const auto tf = core::TransferFunction::preset(g.modality == "CT" ? "ct-soft-tissue" : "mr-default", g.valueMin,
                                                   g.valueMax, g.rescaleSlope, g.rescaleIntercept, space.minSpacing);
    core::BrickCache cache(2ull << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSetOptions options;
    options.cpuMirror = false;
    core::WorkingSet ws(*reader, cache, loader, options);
    ws.converge({view}, tf);
    render::EglOffscreenContext ctx;
    render::GpuRayCaster gpu;
    auto tools = [&](int bits) {
        core::ToolSet t;
        t.clip.enabled = bits & core::ToolSet::ClipBit;
        t.clip.normal = {1, 0, 0};
        t.clip.offset = -centre.x;
        t.focal.enabled = bits & core::ToolSet::FocalBit;
        t.focal.centre = centre;
        t.focal.radii = glm::dvec3(radius * 0.4);
        t.context.enabled = bits & core::ToolSet::ContextBit;
        t.context.centre = centre;
        t.context.radius = radius * 0.5;
        t.band.enabled = bits & core::ToolSet::BandBit;
        t.band.band = {g.valueMin + 0.4 * (g.valueMax - g.valueMin), g.valueMin + 0.5 * (g.valueMax - g.valueMin), g.valueMax,
                       g.valueMax};
        t.mimda.enabled = bits & core::ToolSet::MimdaBit;
        return t;
    };
    auto time = [&](int bits) {
        core::RenderSettings rs;
        rs.tools = tools(bits);
        gpu.render(*reader, ws.index(), ws.slotBricks(), tf, rs, view);  // compile the variant
        const auto t0 = Clock::now();
        for (int f = 0; f < frames; ++f) gpu.render(*reader, ws.index(), ws.slotBricks(), tf, rs, view);
        return std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / frames;
    };
    using T = core::ToolSet;
    const double none = time(0);
    std::printf("%s, %dx%d, %s: no tool %.1f ms/frame\n", argv[1], size, size, ctx.info().renderer.c_str(), none);
    const std::pair<const char*, int> cases[] = {{"clip plane", T::ClipBit},
                                                 {"focal probe", T::FocalBit},
                                                 {"context probe", T::ContextBit},
                                                 {"band picker + MImDA", T::BandBit | T::MimdaBit},
                                                 {"clip + focal + band (three tools)", T::ClipBit | T::FocalBit | T::BandBit}};
    for (const auto& [name, bits] : cases) {
        const double ms = time(bits);
        std::printf("  %-36s %.1f ms/frame (%+.0f%%)\n", name, ms, (ms / none - 1.0) * 100.0);
    }
    return 0;
}
