#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <optional>

#include "app/cli/CliArgs.h"
#include "app/cli/Commands.h"
#include "app/cli/OverlayOptions.h"
#include "core/base/Error.h"
#include "core/image/ImageWriter.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/SliceComposer.h"
#include "core/reference/SliceSampler.h"
#include "core/volume/FramePairing.h"
#include "core/streaming/BrickCache.h"
#include "core/volume/DisplayWindow.h"

#include <glm/geometric.hpp>

namespace hvx::app {

namespace {
/// A volume laid over the base: its reader, cache and sampler.
struct Layer {
    std::unique_ptr<core::OctreeReader> reader;
    core::BrickCache cache{std::size_t(256) << 20};
    std::unique_ptr<core::SliceSampler> sampler;
    explicit Layer(const std::string& path) : reader(core::OctreeReader::open(path)) {
        sampler = std::make_unique<core::SliceSampler>(*reader, cache);
    }
};

}  // namespace

int sliceCommand(int argc, char** argv) {
    const CliArgs args(argc, argv, 2, {"plane", "at", "size", "pixel", "slab", "slab-mode", "window", "level", "scroll", "o", "output",
                                                  "overlay", "labels", "lut", "label-opacity"},
                        {"force-frame", "no-outline", "outline-only"});
    const auto out = args.value("o") ? args.value("o") : args.value("output");
    if (args.positional().size() != 1 || !out)
        throw core::Error("usage: holovox-cli slice FILE.hvo --plane axial|coronal|sagittal|NX,NY,NZ [--at X,Y,Z] "
                          "[--size WxH] [--pixel MM] [--level L (the base volume's octree level; an overlay and labels are sampled at "
                          "the level their own voxels need)] [--slab MM --slab-mode mip|minip|mean] [--window W,L] [--scroll N] "
                          "[--overlay B.hvo[:lut=NAME,opacity=0.5,window=W/L]] [--labels L.hvo [--lut FILE] "
                          "[--label-opacity A] [--no-outline|--outline-only]] [--force-frame] -o OUT.png");
    const auto reader = core::OctreeReader::open(args.positional()[0]);
    const auto& g = reader->geometry();
    core::BrickCache cache(std::size_t(512) << 20);
    const core::SliceSampler sampler(*reader, cache);
    const std::string planeName = args.value("plane").value_or("axial");
    int width = 512, height = 512;
    if (const auto s = args.value("size"); s && std::sscanf(s->c_str(), "%dx%d", &width, &height) != 2)
        throw core::Error("--size must be WxH");
    if (width < 1 || height < 1 || width > 8192 || height > 8192) throw core::Error("--size must be 1x1 to 8192x8192");
    const glm::dvec3 extent = glm::dvec3(g.dims[0], g.dims[1], g.dims[2]) * g.spacing;
    const double pixel = args.value("pixel") ? *args.number("pixel")
                                             : std::max({extent.x, extent.y, extent.z}) / std::min(width, height);
    if (!(pixel > 0)) throw core::Error("--pixel must be above 0 mm");
    glm::dvec3 at = sampler.space().centre();
    if (const auto a = args.value("at")) {
        const auto v = CliArgs::numbers(*a, 3, "--at");
        at = {v[0], v[1], v[2]};
    }
    core::SlicePlane plane;
    if (planeName == "axial") plane = core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, at, pixel, width, height);
    else if (planeName == "coronal")
        plane = core::SlicePlane::standard(core::SlicePlane::Orientation::Coronal, at, pixel, width, height);
    else if (planeName == "sagittal")
        plane = core::SlicePlane::standard(core::SlicePlane::Orientation::Sagittal, at, pixel, width, height);
    else {
        const auto n = CliArgs::numbers(planeName, 3, "--plane");
        plane = core::SlicePlane::oblique({n[0], n[1], n[2]}, at, pixel, width, height);
    }
    // Without --at, through the volume's centre; a native plane there moves onto the nearest
    // layer of voxels (with an even count of slices the centre lies between two).
    if (!args.value("at")) plane.centre = g.onNearestLayer(plane.centre, plane.normal());
    const int level = args.value("level") ? int(args.integer("level", 0, 0, reader->levelCount() - 1)) : -1;
    const std::string m = args.value("slab-mode").value_or("mip");
    const auto mode = m == "mip" ? core::SlabMode::Mip : m == "minip" ? core::SlabMode::MinIp
                      : m == "mean" ? core::SlabMode::Mean
                                    : throw core::Error("--slab-mode must be mip, minip or mean");
    const auto sample = [&] { return args.value("slab") ? sampler.sampleSlab(plane, *args.number("slab"), mode, level)
                                                        : sampler.sample(plane, level); };
    // --scroll N: N slices one after another, a slice apart along the normal (as the wheel
    // steps in the slice views), in this one process with its cache warming; the last is written.
    const long scroll = args.value("scroll") ? args.integer("scroll", 1, 1, 100000) : 1;
    const glm::dvec3 normal = plane.normal();
    double stepMm = 0;
    for (int a = 0; a < 3; ++a) stepMm += std::abs(glm::dot(normal, g.direction[a])) * g.spacing[a];
    const auto started = std::chrono::steady_clock::now();
    core::SliceImage img = sample();
    for (long i = 1; i < scroll; ++i) {
        plane.centre += normal * stepMm;
        img = sample();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (scroll > 1)
        std::printf("scrolled %ld slices %.4g mm apart: %.3f ms per slice (level %d)\n", scroll, stepMm,
                    1000.0 * seconds / double(scroll), img.level);
    at = plane.centre;
    core::DisplayWindow w = core::DisplayWindow::initial(g);
    if (const auto wl = args.value("window")) {
        const auto v = CliArgs::numbers(*wl, 2, "--window");
        if (!(v[0] > 0)) throw core::Error("--window W,L needs a width above 0");
        w = {"", v[1], v[0]};
    }
    if (std::all_of(img.values.begin(), img.values.end(), [](float v) { return std::isnan(v); }))
        throw core::Error("the plane does not cross the volume: nothing to show (check --at)");
    const std::string baseName = args.positional()[0];
    std::unique_ptr<Layer> overlayLayer, labelLayer;
    core::SliceImage overlayImage, labelImage;
    std::optional<core::SliceOverlay> overlay;
    std::optional<core::SliceLabels> labelLayerSettings;
    core::LabelTable table;
    if (const auto spec = args.value("overlay")) {
        const auto [path, opts] = overlaySpec(*spec);
        overlayLayer = std::make_unique<Layer>(path);
        const auto& og = overlayLayer->reader->geometry();
        pairFrames(g, baseName, og, path, args.flag("force-frame"));
        overlayImage = overlayLayer->sampler->sampleLike(plane, img);  // over a slab, the overlay's own slab
        const auto look = overlayLook(opts, og);
        overlay = core::SliceOverlay{&overlayImage, &og, look.map, look.window, look.opacity};
        std::printf("overlay %s: %s map, window W %.6g / L %.6g, opacity %.2g\n", path.c_str(), overlay->map.name().c_str(),
                    overlay->window.width, overlay->window.centre, overlay->opacity);
    }
    if (const auto path = args.value("labels")) {
        labelLayer = std::make_unique<Layer>(*path);
        const auto& lg = labelLayer->reader->geometry();
        if (!lg.isLabel) throw core::Error(*path + " is not a label map (build it with --labels)");
        pairFrames(g, baseName, lg, *path, args.flag("force-frame"));
        labelImage = labelLayer->sampler->sample(plane);
        const auto present = core::SliceComposer::labelsIn(labelImage);
        const std::string sidecar = core::LabelTable::sidecarPath(*path);
        const auto lut = args.value("lut") ? args.value("lut")
                         : std::ifstream(sidecar) ? std::optional<std::string>(sidecar)
                                                  : std::nullopt;
        table = lut ? core::LabelTable::load(*lut) : core::LabelTable::generated(present);
        if (const auto missing = table.addMissing(present); !missing.empty() && lut) {
            std::string list;
            for (const int l : missing) list += (list.empty() ? "" : ", ") + std::to_string(l);
            std::printf("note: label(s) %s are not in %s: drawn in generated colours\n", list.c_str(), lut->c_str());
        }
        const double opacity = args.value("label-opacity") ? *args.number("label-opacity") : 0.5;
        if (!(opacity >= 0 && opacity <= 1)) throw core::Error("--label-opacity must be 0 to 1");
        labelLayerSettings = core::SliceLabels{&labelImage, &table, opacity, !args.flag("outline-only"), !args.flag("no-outline")};
        std::printf("labels %s (%s):", path->c_str(), table.format().c_str());
        for (const int l : present) {
            const auto* e = table.find(l);
            std::printf(" %d %s #%02x%02x%02x;", l, e->name.c_str(), e->rgba[0], e->rgba[1], e->rgba[2]);
        }
        std::printf("%s\n", present.empty() ? " none in this slice" : "");
    }
    if (overlay || labelLayerSettings)
        core::ImageWriter::writeRgbPng(img.width, img.height,
                                       core::SliceComposer::compose(img, g, w, overlay ? &*overlay : nullptr,
                                                                    labelLayerSettings ? &*labelLayerSettings : nullptr),
                                       *out);
    else
        core::ImageWriter::writeGreyPng(img.width, img.height, core::SliceComposer::grey(img, g, w), *out);
    // Without a known orientation the letters would be a guess (left is never right).
    const auto labels = g.orientationAssumed ? std::array<std::string, 4>{"?", "?", "?", "?"} : plane.edgeLabels();
    std::printf("%s plane through (%.4g, %.4g, %.4g) LPS mm, normal (%.4f, %.4f, %.4f); level %d of %d (%s); "
                "%.4g mm pixels\n",
                planeName.c_str(), at.x, at.y, at.z, plane.normal().x, plane.normal().y, plane.normal().z, img.level,
                reader->levelCount(), img.level == 0 ? "full resolution" : "coarser", pixel);
    std::printf("edges: left %s, right %s, top %s, bottom %s\n", labels[0].c_str(), labels[1].c_str(),
                labels[2].c_str(), labels[3].c_str());
    if (img.slabMm > 0) std::printf("slab %.4g mm (%d samples), %s\n", img.slabMm, img.slabSamples,
                                    args.value("slab-mode").value_or("mip").c_str());
    std::printf("window W %.6g / L %.6g; wrote %s (%dx%d)\n", w.width, w.centre, out->c_str(), img.width, img.height);
    return 0;
}

}  // namespace hvx::app
