// holovox-cli lightfield: all views of a multi-view display frame from one working set.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <unistd.h>

#include <glm/geometric.hpp>

#include "app/cli/CliArgs.h"
#include "app/cli/RefractionOption.h"
#include "app/cli/FusedLayer.h"
#include "app/cli/Commands.h"
#include "core/base/AtomicFileWriter.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/camera/DisplayModel.h"
#include "core/base/Error.h"
#include "core/image/ImageWriter.h"
#include "core/image/LightFieldSimulator.h"
#include "core/octree/OctreeReader.h"
#include "core/image/DviPacker.h"
#include "core/image/ProjectorCorrection.h"
#include "core/image/QuiltLayout.h"
#include "core/streaming/ContentBox.h"
#include "core/image/StereoComposer.h"
#include "core/volume/VoxelSourceFactory.h"
#include "core/streaming/WorkingSet.h"
#include "render/EglOffscreenContext.h"
#include "render/LightFieldRenderer.h"

namespace hvx::app {

namespace {
glm::dvec3 parseTriple(const std::string& text, const char* what) {
    const auto v = CliArgs::numbers(text, 3, what);
    return {v[0], v[1], v[2]};
}

/// Fails in words, before any rendering, when an output cannot be written: a folder output's
/// nearest existing ancestor must be a folder that takes a file (the folder itself is made
/// only when the frame is written, so a failed render leaves nothing behind); a file output's
/// folder must exist and take one.
void checkOutputs(const std::string& format, const std::string& out, const std::optional<std::string>& simulate) {
    namespace fs = std::filesystem;
    auto probe = [](const fs::path& folder, const std::string& what) {
        std::error_code ec;
        if (!fs::is_directory(folder.empty() ? fs::path(".") : folder, ec))
            throw core::Error(what + ": the folder " + folder.string() + " does not exist");
        const fs::path test = (folder.empty() ? fs::path(".") : folder) / (".hvx-write-test-" + std::to_string(::getpid()));
        std::ofstream f(test);
        if (!f) throw core::Error(what + ": cannot write into " + (folder.empty() ? std::string(".") : folder.string()));
        f.close();
        fs::remove(test, ec);
    };
    if (format == "projectors" || format == "dvi") {
        std::error_code ec;
        fs::path existing(out);
        while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
        if (!existing.empty() && !fs::is_directory(existing, ec))
            throw core::Error(out + ": cannot make the output folder (" + existing.string() + " is not a folder)");
        probe(existing, out);
    } else {
        probe(fs::path(out).parent_path(), out);
    }
    if (simulate) probe(fs::path(*simulate).parent_path(), *simulate);
}
}  // namespace

int lightFieldCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2,
                       {"display", "o", "output", "format", "eta", "view", "zoom", "tf", "mode", "size", "observer",
                        "simulate", "budget", "cache-mb", "correction", "overlay", "labels", "lut", "label-opacity",
                        "refraction"},
                       {"cpu", "list", "true-depth", "force-frame", "multilevel"});
    if (args.flag("list")) {
        for (const auto& n : core::DisplayModel::builtInNames()) {
            const auto d = core::DisplayModel::load(n);
            std::printf("%-28s %-60s %d views of %dx%d\n", n.c_str(), d.name.c_str(), d.viewCount(), d.viewWidthPx(),
                        d.viewHeightPx());
        }
        return 0;
    }
    const auto out = args.value("o") ? args.value("o") : args.value("output");
    if (args.positional().size() != 1 || !out || !args.value("display"))
        throw core::Error("usage: holovox-cli lightfield FILE.hvo --display PROFILE -o OUT [--format quilt|projectors|exr|stereo|dvi] "
                          "[--eta 0..1] [--view AZ,EL] [--zoom Z] [--true-depth] [--size WxH] [--observer X,Y,Z --simulate OUT.png] [--correction FILE.json] "
                          "[--overlay B.hvo[:lut=NAME,opacity=O,window=W/L] | --labels L.hvo [--lut FILE] [--label-opacity A]] [--refraction N|V:N,...] "
                          "[--force-frame] [--multilevel] [--cpu]");
    const auto display = core::DisplayModel::load(*args.value("display"));
    const std::string format = args.value("format").value_or(
        display.kind == core::DisplayModel::Kind::Lenticular ? "quilt"
        : display.kind == core::DisplayModel::Kind::Stereo  ? "stereo"
                                                            : "projectors");
    // Checked before rendering, which can take minutes.
    if (format != "quilt" && format != "projectors" && format != "exr" && format != "stereo" && format != "dvi")
        throw core::Error("--format must be quilt, projectors, exr, stereo or dvi");
    if (format == "quilt" && display.kind != core::DisplayModel::Kind::Lenticular)
        throw core::Error("--format quilt needs a lenticular display");
    if (format == "stereo" && display.kind != core::DisplayModel::Kind::Stereo)
        throw core::Error("--format stereo needs a stereo display");
    std::optional<core::ProjectorCorrection> correction;
    if (const auto path = args.value("correction")) correction = core::ProjectorCorrection::load(*path);
    const auto reader = core::OctreeReader::open(args.positional()[0], true);  // split-voxel octrees too (DVR)
    if (reader->splitVoxels() && args.value("mode") && *args.value("mode") != "dvr")
        throw core::Error(reader->path() + ": a split-voxel octree is drawn in DVR");
    const auto& g = reader->geometry();
    const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
    const double eta = args.number("eta").value_or(1.0);
    double az = 0, el = 0;
    if (const auto v = args.value("view")) {
        const auto t = parseTriple(*v + ",0", "--view AZ,EL");
        az = t.x;
        el = t.y;
    }
    int width = 0, height = 0;
    if (const auto s = args.value("size")) {
        const auto d = core::VoxelSourceFactory::parseDims(*s + "x1");
        width = int(d[0]);
        height = int(d[1]);
    }
    core::RenderSettings settings;
    const std::string mode = args.value("mode").value_or("dvr");
    if (mode == "mip") settings.mode = core::RenderSettings::Mode::Mip;
    else if (mode != "dvr") throw core::Error("--mode must be dvr or mip for light-field output");
    const std::string preset = args.value("tf").value_or(g.hounsfield() ? "ct-bone" : "mr-default");
    auto tf = core::TransferFunction::preset(preset, g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept,
                                             space.minSpacing);
    applyRefractionOption(args, g,
                          g.isLabel || reader->splitVoxels() || settings.mode != core::RenderSettings::Mode::Dvr ||
                                  args.value("overlay") || args.value("labels")
                              ? "--refraction bends the rays of an image's DVR, drawn alone: not with a label map, "
                                "split-voxels, --mode mip, --overlay or --labels"
                              : "",
                          tf);
    // --multilevel: a display's accuracy s(z) changes the level with depth; bricks of different
    // levels meet without a seam where each samples the cut's level field (thesis §3.2.2, Fig. 3.6).
    settings.multilevel = args.flag("multilevel");
    if (settings.multilevel && (g.isLabel || reader->splitVoxels() || args.value("overlay") || args.value("labels")))
        throw core::Error("--multilevel blends an image's samples across levels: not with a label map, split-voxels, "
                          "--overlay or --labels");
    checkOutputs(format, *out, args.value("simulate"));  // before the first ray: rendering can take minutes
    // Seen from azimuth/elevation like `render`; what the transfer function shows (not the
    // volume's air) framed on the display: its middle on the screen centre, as large as the
    // screen's width and height and the display's sharp depth range allow (DisplayModel::frame).
    const core::View orbit = core::View::orbit(space.centre(), 1000.0, az, el, 8, 8);
    const glm::dvec3 f = glm::normalize(orbit.target - orbit.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(f, orbit.up));
    const glm::dvec3 up = glm::cross(right, f);
    bool content = false;
    const auto framing = core::ContentBox::framing(display, *reader, tf, settings.mode == core::RenderSettings::Mode::Mip,
                                                   right, up, args.flag("true-depth"), &content);
    const double zoom = args.number("zoom").value_or(1.0);
    const double scale = zoom * framing.scale, depthScale = zoom * framing.depthScale;
    std::printf("framed %s: %.4g display mm per patient mm across (the screen's %s), %.4g in depth (%s; sharp "
                "depth range +/- %.3g mm)\n",
                content ? "what the transfer function shows" : "the whole volume (the transfer function shows nothing)",
                framing.scale, framing.limit, framing.depthScale,
                framing.depthScale < framing.scale * 0.999 ? "compressed to fit it" : "true depth", display.depthRangeMm());
    const auto views = display.views(framing.centre, right, up, eta, width, height, scale, depthScale);

    core::WorkingSetOptions opt;
    opt.maxBricks = std::size_t(args.integer("budget", 8192, 1, 1 << 20));
    opt.cpuMirror = args.flag("cpu");
    opt.cullByTransferFunction = settings.mode == core::RenderSettings::Mode::Dvr;
    const std::size_t cacheBytes = std::size_t(args.integer("cache-mb", 2048, 16, 1 << 20)) << 20;
    core::BrickCache cache(cacheBytes);
    core::BrickLoader loader(*reader, cache);
    core::WorkingSet ws(*reader, cache, loader, opt);
    // --overlay or --labels: a second volume fused in every view (its own cut, the same budget).
    std::unique_ptr<FusedLayer> fused;
    std::optional<render::LightFieldRenderer::Fused> fusedViews;
    if (const auto spec = args.value("overlay") ? args.value("overlay") : args.value("labels")) {
        if (args.value("overlay") && args.value("labels")) throw core::Error("one volume at a time is fused: --overlay or --labels");
        if (settings.mode != core::RenderSettings::Mode::Dvr) throw core::Error("two volumes are fused in DVR only");
        if (reader->splitVoxels()) throw core::Error(reader->path() + ": a split-voxel octree is drawn alone");
        fused = std::make_unique<FusedLayer>(*spec, args.value("labels").has_value(), args, g, cacheBytes, opt);
        fusedViews.emplace(render::LightFieldRenderer::Fused{*fused->reader, fused->ws, *fused->tf});
    } else if (args.value("lut") || args.value("label-opacity")) {
        throw core::Error("--lut and --label-opacity go with --labels");
    }
    render::LightFieldRenderer::Stats stats;
    std::vector<core::RenderImage> images;
    std::string device = "the CPU";
    std::unique_ptr<render::EglOffscreenContext> context;
    std::unique_ptr<render::GpuRayCaster> gpu;
    if (!args.flag("cpu")) {
        context = std::make_unique<render::EglOffscreenContext>();
        gpu = std::make_unique<render::GpuRayCaster>();
        device = "the GPU (" + context->info().renderer + ")";
    }
    images = render::LightFieldRenderer::render(*reader, ws, loader, tf, settings, views, display.accuracyFunction(scale, depthScale),
                                                gpu.get(), true, &stats, nullptr, fusedViews ? &*fusedViews : nullptr);

    if (correction)  // per-projector warp and colour LUTs
        for (std::size_t i = 0; i < images.size(); ++i) images[i] = correction->apply(images[i], i);
    std::string written;
    if (format == "exr") {
        std::vector<std::string> names;
        for (std::size_t i = 0; i < images.size(); ++i) names.push_back("view" + std::to_string(i));
        core::ImageWriter::writeExrParts(images, names, *out);
        written = *out + " (" + std::to_string(images.size()) + " parts)";
    } else if (format == "quilt") {
        if (display.kind != core::DisplayModel::Kind::Lenticular) throw core::Error("--format quilt needs a lenticular display");
        core::QuiltLayout q{display.quiltColumns, display.quiltRows, images.front().width, images.front().height, display.aspect};
        const std::string path = q.fileName(*out);
        core::ImageWriter::write(q.assemble(images), path);
        std::ostringstream meta;  // the layout beside the quilt, written whole or not at all
        meta << "{\"quilt\": {\"columns\": " << q.columns << ", \"rows\": " << q.rows << ", \"aspect\": " << q.aspect
             << ", \"tileWidth\": " << q.tileWidth << ", \"tileHeight\": " << q.tileHeight << ", \"viewConeDegrees\": "
             << display.viewConeDegrees << ", \"view0\": \"bottom-left, leftmost\"}, \"display\": \"" << display.name << "\"}\n";
        core::AtomicFileWriter sidecar(path.substr(0, path.size() - 4) + ".json");
        const std::string text = meta.str();
        sidecar.append(text.data(), text.size());
        sidecar.commit();
        written = path;
    } else if (format == "stereo") {
        if (display.kind != core::DisplayModel::Kind::Stereo) throw core::Error("--format stereo needs a stereo display");
        core::ImageWriter::write(core::StereoComposer::compose(display.layout, images[0], images[1]), *out);
        written = *out;
    } else if (format == "projectors") {
        std::filesystem::create_directories(*out);
        for (std::size_t i = 0; i < images.size(); ++i) {
            char name[48];
            std::snprintf(name, sizeof name, "view_%03zu.png", i);
            core::ImageWriter::write(images[i], (std::filesystem::path(*out) / name).string());
        }
        written = *out + "/view_*.png (" + std::to_string(images.size()) + " images)";
    } else if (format == "dvi") {
        const auto frames = core::DviPacker::pack(images);
        std::filesystem::create_directories(*out);
        for (std::size_t i = 0; i < frames.size(); ++i) {
            char name[48];
            std::snprintf(name, sizeof name, "dvi_frame_%02zu.png", i);
            core::ImageWriter::write(frames[i], (std::filesystem::path(*out) / name).string());
        }
        written = *out + "/dvi_frame_*.png (" + std::to_string(frames.size()) + " frames of 1280x1024)";
    } else {
        throw core::Error("--format must be quilt, projectors, exr, stereo or dvi");
    }
    if (const auto sim = args.value("simulate")) {
        const glm::dvec3 observer = args.value("observer") ? parseTriple(*args.value("observer"), "--observer")
                                                           : glm::dvec3(0, display.observerHeightMm, display.observerDistanceMm);
        core::ImageWriter::write(core::LightFieldSimulator::observe(display, images, observer), *sim);
        written += ", simulated view " + *sim;
    }
    const double beams = double(images.size()) * images.front().width * images.front().height;
    std::printf("%s: %zu views of %dx%d on %s, one cut of %zu bricks (%d frames, %.0f ms), ray casting %.0f ms "
                "(%.1f views/s, %.2f Mbeams/s); wrote %s\n",
                display.name.c_str(), images.size(), images.front().width, images.front().height, device.c_str(),
                stats.cutNodes, stats.refineFrames, stats.refineMs, stats.renderMs,
                double(images.size()) / (stats.renderMs / 1000.0), beams / 1e6 / (stats.renderMs / 1000.0), written.c_str());
    if (fused)
        std::printf("fused %s (%s): cut of %zu bricks (%zu loaded)\n", fused->path.c_str(), fused->description.c_str(),
                    fused->ws.stats().cutNodes, fused->loader.loadedCount());
    return 0;
}

}  // namespace hvx::app
