// epoxy first: it must precede any desktop GL header (Qt's included).
#include <epoxy/gl.h>

#include "ui/VolumeViewScene.h"

#include <cmath>

#include "core/base/Error.h"
#include "core/image/ImageWriter.h"
#include "core/streaming/ContentBox.h"
#include "render/GpuRayCaster.h"
#include "render/LightFieldRenderer.h"
#include "ui/ImageConversion.h"

namespace hvx::ui {

void VolumeView::capture(const QString& path, int width, int height) {
    if (!scene_ || !tf_ || !gpu_) throw core::Error("nothing to capture: no volume is open");
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw core::Error("capture size must be between 1x1 and 16384x16384");
    makeCurrent();
    try {
        core::RenderSettings rs = settings_;
        const auto img = renderFrame(camera_.view(width, height), rs, true);
        doneCurrent();
        core::ImageWriter::write(img, path.toStdString());
    } catch (...) {
        doneCurrent();
        throw;
    }
    update();
}

QImage VolumeView::renderLevel(std::shared_ptr<const core::OctreeReader> reader, int level, bool nearest, QSize size) {
    if (!scene_ || !tf_ || !gpu_ || !reader) throw core::Error("open a volume first");
    if (level < 0 || level >= reader->levelCount())
        throw core::Error(reader->path() + " has no level " + std::to_string(level));
    core::RenderSettings rs = settings_;
    rs.mode = core::RenderSettings::Mode::Dvr;
    rs.nearest = nearest && !reader->splitVoxels();
    core::WorkingSetOptions o;
    o.cpuMirror = false;
    o.voxelsPerPixel = 1e-6;
    o.finestLevel = level;
    o.crop = scene_->ws.options().crop;
    Scene scene(std::move(reader), o, std::size_t(512) << 20);
    const auto view = camera_.view(size.width(), size.height());
    // The three reconstructions side by side, without refraction (split-voxels are drawn without it).
    const auto& tf = straightTf_ ? *straightTf_ : *tf_;
    scene.ws.converge({view}, tf, {}, 256);
    makeCurrent();
    try {
        const auto img = gpu_->render(*scene.reader, scene.ws.index(), scene.ws.slotBricks(), tf, rs, view);
        glUseProgram(0);
        for (GLuint unit = 0; unit < 3; ++unit) glBindTextureUnit(unit, 0);
        doneCurrent();
        return toQImage(img);
    } catch (...) {
        doneCurrent();
        throw;
    }
}

std::vector<core::RenderImage> VolumeView::renderViews(const core::DisplayModel& display, double eta, double zoom,
                                                       double maxBeams, bool interactive, core::JobContext* job) {
    if (!scene_ || !tf_ || !gpu_) throw core::Error("open a volume first");
    // What the transfer function shows fills the screen's width (or height) and the display's
    // sharp depth range (core::DisplayModel::frame), about the camera's target.
    const auto framing = core::ContentBox::framing(display, *scene_->reader, *tf_,
                                                   settings_.mode != core::RenderSettings::Mode::Dvr, camera_.right(),
                                                   camera_.up(), false);
    const double scale = zoom * framing.scale, depthScale = zoom * framing.depthScale;
    const double beams = double(display.viewCount()) * display.viewWidthPx() * display.viewHeightPx();
    double shrink = beams > maxBeams ? std::sqrt(maxBeams / beams) : 1.0;
    core::RenderSettings rs = settings_;
    if (interactive) {  // thesis §5.5: 2.5 mm on screen and a doubled integration step
        const double pixelMm = display.screenHeightMm / std::max(1, display.viewHeightPx());
        shrink *= std::min(0.5, pixelMm / 2.5);
        rs.stepScale *= 2.0;
    }
    const auto views = display.views(camera_.target(), camera_.right(), camera_.up(), eta,
                                     std::max(1, int(display.viewWidthPx() * shrink)),
                                     std::max(1, int(display.viewHeightPx() * shrink)), scale, depthScale);
    // What the 3D view draws: the fused volume over the open one (DVR without tools), else the
    // split-voxel octree (DVR), else the volume's own octree.
    const bool dvr = rs.mode == core::RenderSettings::Mode::Dvr;
    const bool fusedToo = fused_ && fusedTf_ && dvr && !rs.tools.variantBits();
    Scene& scene = split_ && dvr && !fusedToo ? *split_ : *scene_;
    makeCurrent();
    try {
        core::WorkingSetOptions options = scene.ws.options();
        options.cpuMirror = false;
        core::WorkingSet ws(*scene.reader, scene.cache, scene.loader, options);
        std::optional<core::WorkingSet> fusedWs;
        std::optional<render::LightFieldRenderer::Fused> fused;
        if (fusedToo) {
            core::WorkingSetOptions o = fused_->ws.options();
            o.cpuMirror = false;
            o.crop = {};
            fusedWs.emplace(*fused_->reader, fused_->cache, fused_->loader, o);
            fused.emplace(render::LightFieldRenderer::Fused{*fused_->reader, *fusedWs, *fusedTf_});
        }
        auto images = render::LightFieldRenderer::render(*scene.reader, ws, scene.loader,
                                                         drawnTf(rs, fusedToo, &scene == split_.get()), rs, views,
                                                         display.accuracyFunction(scale, depthScale), gpu_.get(), true, nullptr,
                                                         job, fused ? &*fused : nullptr);
        glUseProgram(0);
        for (GLuint unit = 0; unit < 3; ++unit) glBindTextureUnit(unit, 0);
        doneCurrent();
        update();
        return images;
    } catch (...) {
        doneCurrent();
        throw;
    }
}

}  // namespace hvx::ui
