// Tools benchmark (not a test): the frame-time cost of each illustrative tool, and of three
// together, against no tool, in the same run (GPU ray caster through EGL; the thesis reports
// about 10%).
//
//   build/release/tests/bench/hvx_bench_tools FILE.hvo [--size 512] [--frames 5] [--breakdown] [--tf PRESET]
//        [--opacity S]   (S scales the preset's opacity: the thesis measured semi-transparent functions)
//        [--save DIR]    (writes each case's frame as DIR/NN-case.png, to look at)
//        [--context-step K]  (the focal probe's context step, ToolSet::FocalProbe::contextStep; default its default)
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/appearance/TransferFunctionSpec.h"
#include "core/image/ImageWriter.h"
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
        std::fprintf(stderr, "usage: %s FILE.hvo [--size N] [--frames N] [--breakdown]\n", argv[0]);
        return 2;
    }
    int size = 512, frames = 5;
    bool breakdown = false;
    std::string preset, saveDir;
    double opacity = 1.0;
    double contextStep = core::ToolSet{}.focal.contextStep;
    for (int i = 2; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--breakdown")) breakdown = true;
        else if (!std::strcmp(argv[i], "--size") && i + 1 < argc) size = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--tf") && i + 1 < argc) preset = argv[++i];
        else if (!std::strcmp(argv[i], "--opacity") && i + 1 < argc) opacity = std::atof(argv[++i]);
        else if (!std::strcmp(argv[i], "--save") && i + 1 < argc) saveDir = argv[++i];
        else if (!std::strcmp(argv[i], "--context-step") && i + 1 < argc) contextStep = std::atof(argv[++i]);
    }
    const auto reader = core::OctreeReader::open(argv[1]);
    const auto& g = reader->geometry();
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    const glm::dvec3 centre = space.centre();
    const glm::dvec3 corner(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const double radius = glm::length(centre - corner);
    const auto view = core::View::orbit(centre, radius / std::tan(glm::radians(15.0)) * 1.05, 30, 15, size, size);
    if (!(opacity > 0.0 && opacity <= 1.0)) {
        std::fprintf(stderr, "--opacity scales the preset's opacity: a number above 0 and at most 1\n");
        return 2;
    }
    if (preset.empty()) preset = g.modality == "CT" ? "ct-soft-tissue" : "mr-default";
    core::TransferFunction tf({{g.valueMin, glm::dvec4(0.0)}, {g.valueMax, glm::dvec4(0.0)}}, g.valueMin, g.valueMax);
    try {
        auto spec = core::TransferFunctionSpec::from(core::TransferFunction::preset(
            preset, g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept, space.minSpacing));
        for (auto& p : spec.opacity) p.alpha *= opacity;
        tf = spec.build(g.valueMin, g.valueMax, space.minSpacing);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
        return 2;
    }
    core::BrickCache cache(2ull << 30);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSetOptions options;
    options.cpuMirror = false;
    core::WorkingSet ws(*reader, cache, loader, options);
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
        t.focal.contextStep = contextStep;
        t.context.enabled = bits & core::ToolSet::ContextBit;
        t.context.centre = centre;
        t.context.radius = radius * 0.5;
        t.band.enabled = bits & core::ToolSet::BandBit;
        t.band.band = {g.valueMin + 0.4 * (g.valueMax - g.valueMin), g.valueMin + 0.5 * (g.valueMax - g.valueMin), g.valueMax,
                       g.valueMax};
        t.mimda.enabled = bits & core::ToolSet::MimdaBit;
        return t;
    };
    // Cases are timed in rounds, one frame of each case per round, and each case's median is
    // reported: this shared machine's speed drifts over seconds, which would otherwise bias
    // whichever case ran during a slow spell.
    struct Case {
        std::string name;
        core::RenderSettings rs;
        std::vector<double> ms;
    };
    using T = core::ToolSet;
    std::vector<Case> cases;
    auto add = [&](std::string name, int bits, double earlyTermination = 0.99, double stepScale = 1.0) {
        Case c{std::move(name), {}, {}};
        c.rs.tools = tools(bits);
        c.rs.earlyTermination = earlyTermination;
        c.rs.stepScale = stepScale;
        cases.push_back(std::move(c));
    };
    add("no tool", 0);
    add("clip plane", T::ClipBit);
    add("focal probe", T::FocalBit);
    add("context probe", T::ContextBit);
    add("band picker + MImDA", T::BandBit | T::MimdaBit);
    add("clip + focal + band (three tools)", T::ClipBit | T::FocalBit | T::BandBit);
    if (breakdown) {  // where the probes' time goes (README: Tool cost)
        // Seen across its axis, the context probe's front half is hidden outright (omega_a = 0):
        // the ray caster skips its gradients and enhancers there (core::glsl::hvxHidden).
        add("context probe, axis across the view", T::ContextBit);
        const glm::dvec3 forward = glm::normalize(view.target - view.eye);
        cases.back().rs.tools.context.axis = glm::normalize(glm::cross(forward, view.up));
        // In the focus cone the rays start and end at the probe's bounding sphere
        // (core::glsl::hvxVisibleSpan); a wide cone shows what that saves.
        add("focal probe, focus cone 0.9 of the probe", T::FocalBit);
        cases.back().rs.tools.focal.rho = 0.9;
        // What seeing the inside costs by itself: the front half cut away by a clip plane seen
        // face-on through the probes' centre (a plain cut, tests/render/ToolsTest.cpp).
        add("cut face-on through the centre", T::ClipBit);
        cases.back().rs.tools.clip.normal = -forward;
        cases.back().rs.tools.clip.offset = glm::dot(forward, centre);
        add("no tool, rays never stop early", 0, 2.0);
        add("focal probe, rays never stop early", T::FocalBit, 2.0);
        add("focal probe, half the samples", T::FocalBit, 0.99, 2.0);
        // The context sampled as densely as the focus (ToolSet::FocalProbe::contextStep 1).
        add("focal probe, context every sample", T::FocalBit);
        cases.back().rs.tools.focal.contextStep = 1;
        add("context probe, half the samples", T::ContextBit, 0.99, 2.0);
    }
    ws.converge({view}, tf);
    for (std::size_t i = 0; i < cases.size(); ++i) {  // compile the variants
        const auto image = gpu.render(*reader, ws.index(), ws.slotBricks(), tf, cases[i].rs, view);
        if (saveDir.empty()) continue;
        std::string name = cases[i].name;
        for (char& ch : name)
            if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '-';
        char file[32];
        std::snprintf(file, sizeof file, "%02zu-", i);
        core::ImageWriter::write(image, saveDir + "/" + file + name + ".png");
    }
    for (int r = 0; r < frames; ++r)
        for (auto& c : cases) {
            const auto t0 = Clock::now();
            gpu.render(*reader, ws.index(), ws.slotBricks(), tf, c.rs, view);
            c.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        }
    auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    };
    const double none = median(cases[0].ms);
    std::printf("%s, %dx%d, %s, tf %s at %g of its opacity, focal context step %g, median of %d interleaved rounds: "
                "no tool %.1f ms/frame\n",
                argv[1], size, size, ctx.info().renderer.c_str(), preset.c_str(), opacity, contextStep, frames, none);
    for (std::size_t i = 1; i < cases.size(); ++i) {
        const double ms = median(cases[i].ms);
        std::printf("  %-40s %.1f ms/frame (%+.0f%%)\n", cases[i].name.c_str(), ms, (ms / none - 1.0) * 100.0);
    }
    return 0;
}
