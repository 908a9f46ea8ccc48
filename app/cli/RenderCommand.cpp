#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "app/cli/FusedLayer.h"
#include "app/cli/RefractionOption.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/reference/CpuRayCaster.h"
#include "core/reference/FusedRayCaster.h"
#include "core/appearance/LabelTable.h"
#include "core/base/Error.h"
#include "core/image/ImageWriter.h"
#include "core/octree/OctreeReader.h"
#include "core/volume/VoxelSourceFactory.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StudyDatabase.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/GpuRayCaster.h"

namespace hvx::app {

namespace {
core::RenderSettings::Mode parseMode(const std::string& m) {
    if (m == "dvr") return core::RenderSettings::Mode::Dvr;
    if (m == "iso") return core::RenderSettings::Mode::Iso;
    if (m == "mip") return core::RenderSettings::Mode::Mip;
    if (m == "minip") return core::RenderSettings::Mode::MinIp;
    if (m == "xray" || m == "average") return core::RenderSettings::Mode::Average;
    throw core::Error("--mode must be dvr, iso, mip, minip or xray");
}
/// The octree to render: the file given, or with --time N the N-th time point (volume) of the
/// 4D series whose UID is given, from the study database (built there first when it has no
/// octree yet, and recorded for the next time).
std::string timePoint(const CliArgs& args) {
    const std::string& given = args.positional()[0];
    if (!args.value("time")) return given;
    if (given.size() > 4 && given.substr(given.size() - 4) == ".hvo")
        throw core::Error("--time picks a time point of a 4D series: give the series' UID (and --db), not an octree");
    dicom::StudyDatabase db(args.value("db").value_or(dicom::StudyDatabase::defaultPath()));
    const auto volumes = db.volumesOfSeries(given);
    if (volumes.size() < 2)
        throw core::Error("series " + given + (db.filesOfSeries(given).empty() ? " is not in the database (import it first)"
                                                                              : " is not a 4D series: --time needs several volumes"));
    const auto n = std::size_t(args.integer("time", 1, 1, long(volumes.size())));
    const auto& row = volumes[n - 1];
    std::printf("time point %zu of %zu: %s\n", n, volumes.size(), row.varying.c_str());
    if (!row.octreePath.empty() && std::filesystem::exists(row.octreePath)) return row.octreePath;
    core::JobContext job;
    std::vector<std::string> warnings;
    const auto path = dicom::SeriesOctree::build(db, given, job, &warnings, {}, row.number);
    for (const auto& w : warnings) std::fprintf(stderr, "holovox-cli: warning: %s\n", w.c_str());
    std::printf("built its octree: %s\n", path.c_str());
    return path;
}

}  // namespace

int renderCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2,
                       {"view", "mode", "tf", "size", "o", "output", "iso", "budget", "accuracy", "cache-mb", "boundary",
                        "view-transparency", "unsharp", "exaggerated", "tools", "crop", "lut", "label-opacity", "overlay", "labels", "time", "db", "gradient-opacity",
                        "level", "refraction"},
                       {"cpu", "force-frame", "nearest", "multilevel"});
    const auto out = args.value("o") ? args.value("o") : args.value("output");
    if (args.positional().size() != 1 || !out)
        throw core::Error("usage: holovox-cli render FILE.hvo|SERIES_UID --time N [--db FILE] [--cpu] [--view AZ,EL,ZOOM] [--mode dvr|iso|mip|minip|xray] "
                          "[--tf PRESET | --lut LABELS.txt [--label-opacity A]] [--overlay B.hvo[:lut=NAME,opacity=0.5,window=W/L] | "
                          "--labels L.hvo [--lut FILE] [--label-opacity A]] [--force-frame] [--level L] [--nearest] [--multilevel] [--size WxH] [--boundary 0..1] [--view-transparency 0..1] [--unsharp 0..8] [--exaggerated 0..1] [--gradient-opacity G:S,...] [--refraction N|V:N,...] [--tools TOOLS.json] [--crop I0,J0,K0,I1,J1,K1] -o OUT.png|OUT.exr");
    // A split-voxel octree: its cells walked by a DDA (GPU: raycast_split.glsl; --cpu: SplitCellMarch).
    const auto reader = core::OctreeReader::open(timePoint(args), true);
    if (reader->splitVoxels() && (args.value("overlay") || args.value("labels") || args.value("gradient-opacity")))
        throw core::Error(reader->path() + ": a split-voxel octree is drawn alone, without --overlay, --labels or --gradient-opacity");
    if (reader->splitVoxels() && args.value("mode") && *args.value("mode") != "dvr")
        throw core::Error(reader->path() + ": a split-voxel octree is drawn in DVR");
    const auto& g = reader->geometry();
    double az = 0, el = 0, zoom = 1;
    if (const auto v = args.value("view")) {
        char c1 = 0, c2 = 0;
        std::istringstream in(*v);
        if (!(in >> az >> c1 >> el >> c2 >> zoom) || c1 != ',' || c2 != ',' || !(zoom > 0))
            throw core::Error("--view must be AZIMUTH,ELEVATION,ZOOM in degrees and a positive factor, e.g. 30,15,1.2");
    }
    int width = 512, height = 512;
    if (const auto s = args.value("size")) {
        const auto d = core::VoxelSourceFactory::parseDims(*s + "x1");
        width = int(d[0]);
        height = int(d[1]);
        if (width > 16384 || height > 16384) throw core::Error("--size is limited to 16384x16384");
    }
    core::RenderSettings settings;
    settings.mode = parseMode(args.value("mode").value_or("dvr"));
    settings.boundary = args.number("boundary").value_or(0.0);
    settings.viewTransparency = args.number("view-transparency").value_or(0.0);
    if (!(settings.boundary >= 0 && settings.boundary <= 1) || !(settings.viewTransparency >= 0 && settings.viewTransparency <= 1))
        throw core::Error("--boundary and --view-transparency must be between 0 and 1");
    settings.normalUnsharp = args.number("unsharp").value_or(0.0);
    settings.exaggeratedShading = args.number("exaggerated").value_or(0.0);
    if (!(settings.normalUnsharp >= 0 && settings.normalUnsharp <= 8))
        throw core::Error("--unsharp (normal unsharp masking) must be between 0 and 8");
    if (!(settings.exaggeratedShading >= 0 && settings.exaggeratedShading <= 1))
        throw core::Error("--exaggerated (exaggerated shading) must be between 0 and 1");
    if (const auto tools = args.value("tools")) {  // illustrative tools from JSON (core::ToolSet)
        std::ifstream in(*tools);
        if (!in) throw core::Error(*tools + ": cannot be read");
        std::ostringstream text;
        text << in.rdbuf();
        try {
            settings.tools = core::ToolSet::fromJson(text.str());
        } catch (const core::Error& e) {
            throw core::Error(*tools + ": " + e.what());
        }
    }
    std::string preset = args.value("tf").value_or(g.hounsfield() ? "ct-bone" : "mr-default");
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    const bool fusedLabels = args.value("labels").has_value();
    if (fusedLabels && args.value("overlay")) throw core::Error("one volume at a time is fused in 3D: --overlay or --labels");
    if (g.isLabel && args.value("tf")) throw core::Error("a label map is drawn with its label table (--lut), not a --tf preset");
    if (!g.isLabel && !fusedLabels && (args.value("lut") || args.value("label-opacity")))
        throw core::Error(args.positional()[0] + " is not a label map: --lut and --label-opacity are for label maps");
    if (g.isLabel && fusedLabels) throw core::Error(args.positional()[0] + " is a label map: --labels lays one over an image");
    const auto tf = [&] {
        if (!g.isLabel)
            return core::TransferFunction::preset(preset, g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                                  space.minSpacing);
        // A label map: each label in its table's colour, never blended with a neighbour's.
        const auto table = core::LabelTable::forLabelMap(args.positional()[0], g.valueMin, g.valueMax,
                                                         args.value("lut").value_or(""));
        const double opacity = args.number("label-opacity").value_or(1.0);
        if (!(opacity >= 0 && opacity <= 1)) throw core::Error("--label-opacity must be 0 to 1");
        preset = "labels (" + table.format() + ")";
        return core::TransferFunction::forLabels(table, opacity, space.minSpacing);
    }();
    // --gradient-opacity G0:S0,G1:S1,...: opacity scaled by S at gradient magnitude G (physical
    // units per mm, e.g. HU/mm), linear between, constant beyond (MedVis §3.2.1).
    auto rendered = tf;
    if (const auto curve = args.value("gradient-opacity")) {
        if (g.isLabel) throw core::Error("--gradient-opacity is for images, not label maps");
        std::vector<core::TransferFunction::GradientPoint> points;
        for (const auto& [m, scale] : CliArgs::pairs(*curve, "--gradient-opacity", "GRADIENT:SCALE", "0:0,50:1"))
            points.push_back({m / std::abs(g.rescaleSlope), scale});
        rendered.setGradientOpacity(std::move(points));
    }
    // --refraction: the rays bend by Snell's law (an image's DVR, drawn alone without tools).
    applyRefractionOption(args, g,
                          g.isLabel || reader->splitVoxels() || settings.mode != core::RenderSettings::Mode::Dvr ||
                                  settings.tools.any() || args.value("overlay") || args.value("labels")
                              ? "--refraction bends the rays of an image's DVR, drawn alone without --tools: not with a label "
                                "map, split-voxels, --mode other than dvr, --tools, --overlay or --labels"
                              : "",
                          rendered);
    core::WorkingSetOptions opt;
    opt.maxBricks = std::size_t(args.integer("budget", 4096, 1, 1 << 20));
    opt.voxelsPerPixel = args.number("accuracy").value_or(1.0);
    // --level L: that level wherever the view reaches it (the thesis's Fig. 4.6 compares
    // reconstructions at one level); --nearest: each sample takes its voxel's value.
    if (args.value("level")) {
        if (args.value("accuracy")) throw core::Error("--level and --accuracy each choose the detail: give one");
        opt.finestLevel = int(args.integer("level", 0, 0, reader->levelCount() - 1));
        opt.voxelsPerPixel = 1e-6;
    }
    settings.nearest = args.flag("nearest");
    if (settings.nearest && (reader->splitVoxels() || g.isLabel))
        throw core::Error("--nearest is for an image's voxels: a label map is always read nearest, a split-voxel octree by its planes");
    // --multilevel: leaves beside coarser ones blend with their parents (thesis §3.2.2, Fig. 3.6).
    settings.multilevel = args.flag("multilevel");
    if (settings.multilevel && (settings.nearest || reader->splitVoxels() || g.isLabel || args.value("overlay") || args.value("labels")))
        throw core::Error("--multilevel blends an image's trilinear samples across levels: not with --nearest, a label map, "
                          "split-voxels, --overlay or --labels");
    opt.cpuMirror = args.flag("cpu");  // the GPU pool takes bricks in their stored type
    opt.cullByTransferFunction = settings.mode == core::RenderSettings::Mode::Dvr;
    if (settings.mode == core::RenderSettings::Mode::Iso) {
        const double physical = args.number("iso").value_or(g.hounsfield() ? 300.0 : 0.5 * (g.valueMin + g.valueMax));
        settings.isoValue = (physical - g.rescaleIntercept) / g.rescaleSlope;
        opt.isosurface = true;
        opt.isoValue = settings.isoValue;
    }
    // An orbit camera around the volume's centre that frames it.
    const glm::dvec3 centre = space.centre();
    const glm::dvec3 corner = glm::dvec3(space.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
    const double radius = glm::length(centre - corner) / std::tan(glm::radians(15.0)) * 1.05 / zoom;
    const core::View view = core::View::orbit(centre, radius, az, el, width, height);

    // A clip plane seen face-on hides its far side from every ray: those bricks are not loaded.
    opt.clip = settings.tools.clipHides(view);
    opt.clipPlane = settings.tools.keptHalfSpace();
    // --crop I0,J0,K0,I1,J1,K1: millimetres from the volume's first corner along its axes.
    if (const auto crop = args.value("crop")) {
        const auto v = CliArgs::numbers(*crop, 6, "--crop");
        settings.crop = core::CropBox::fromMillimetres({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, g.dims, g.spacing);
    }
    opt.crop = settings.crop;
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t cacheBytes = std::size_t(args.integer("cache-mb", 2048, 16, 1 << 20)) << 20;
    core::BrickCache cache(cacheBytes);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSet ws(*reader, cache, loader, opt);
    // Synchronous: load what the cut asks for (a transparent but refracting brick is content).
    const int frames = ws.converge({view}, rendered);
    // --overlay or --labels: a second volume fused in the same ray march, with its own working
    // set (the same budget) and transfer function.
    std::unique_ptr<FusedLayer> fused;
    if (const auto spec = args.value("overlay") ? args.value("overlay") : args.value("labels")) {
        if (settings.mode != core::RenderSettings::Mode::Dvr) throw core::Error("two volumes are fused in 3D in DVR only");
        if (settings.tools.variantBits()) throw core::Error("the illustrative tools are not drawn over a fused volume");
        fused = std::make_unique<FusedLayer>(*spec, fusedLabels, args, g, cacheBytes, opt);
        fused->ws.converge({view}, *fused->tf);
    }
    const double refineSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const auto& e : loader.errors()) std::fprintf(stderr, "holovox-cli: warning: %s (drawn coarser)\n", e.c_str());
    const auto t1 = std::chrono::steady_clock::now();
    core::RenderImage image;
    std::string device = "the CPU";
    if (args.flag("cpu")) {
        const core::CpuRayCaster base(*reader, ws.index(), ws.slotData(), rendered, settings);
        if (fused) {
            core::RenderSettings plain = settings;
            plain.crop = {};
            const core::CpuRayCaster second(*fused->reader, fused->ws.index(), fused->ws.slotData(), *fused->tf, plain);
            image = core::FusedRayCaster(base, second).render(view);
        } else {
            image = base.render(view);
        }
    } else {
        render::EglOffscreenContext context;  // headless: EGL surfaceless (Mesa) or an EGL device
        render::GpuRayCaster gpu;
        std::optional<render::GpuRayCaster::Overlay> overlay;
        if (fused) overlay.emplace(render::GpuRayCaster::Overlay{*fused->reader, fused->ws.index(), fused->ws.slotBricks(), *fused->tf});
        image = gpu.render(*reader, ws.index(), ws.slotBricks(), rendered, settings, view, overlay ? &*overlay : nullptr);
        device = "the GPU (" + context.info().renderer + ")";
    }
    const double renderSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    core::ImageWriter::write(image, *out);
    std::printf(
        "rendered %s (%dx%d, %s, tf %s) on %s: cut of %zu bricks (%zu loaded, %zu frames to converge, "
        "%.2f s), ray casting %.2f s\n",
        out->c_str(), width, height, args.value("mode").value_or("dvr").c_str(), preset.c_str(), device.c_str(),
        ws.stats().cutNodes, loader.loadedCount(), std::size_t(frames), refineSeconds, renderSeconds);
    if (fused)
        std::printf("fused %s (%s): cut of %zu bricks (%zu loaded)\n", fused->path.c_str(), fused->description.c_str(),
                    fused->ws.stats().cutNodes, fused->loader.loadedCount());
    return 0;
}

}  // namespace hvx::app
