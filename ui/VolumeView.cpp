// epoxy first: it must precede any desktop GL header (Qt's included).
#include <epoxy/gl.h>

#include "ui/VolumeView.h"

#include <QSurfaceFormat>

#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/base/Error.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "render/GpuRayCaster.h"
#include "render/LightFieldRenderer.h"
#include "ui/EdgeLabels.h"
#include "ui/MeasurementOverlay.h"
#include "ui/ImageConversion.h"
#include "ui/VolumeViewScene.h"

namespace hvx::ui {

VolumeView::VolumeView(QWidget* parent) : QOpenGLWidget(parent) {
    setFocusPolicy(Qt::StrongFocus);
    setMinimumSize(200, 200);
    setToolTip(tr("Left drag: rotate \u2022 Middle or Shift+drag: pan \u2022 Right drag or wheel: zoom\n"
                  "A P L R S I: standard views \u2022 Home: reset \u2022 D, then two clicks: a distance on the surface "
                  "\u2022 B, then two clicks: a sphere's centre and rim on the surface, with its statistics\n"
                  "Ctrl+click: place the probes on the surface \u2022 Ctrl+drag: move them (with Shift: in depth) "
                  "\u2022 Ctrl+wheel: scale them \u2022 Alt+click: pick a band\n"
                  "Clip plane alone: Ctrl+drag pushes it along its normal, Ctrl+Shift+drag tilts it"));
    settle_.setSingleShot(true);
    settle_.setInterval(200);
    connect(&settle_, &QTimer::timeout, this, qOverload<>(&VolumeView::update));
    refine_.setSingleShot(true);
    refine_.setInterval(15);
    connect(&refine_, &QTimer::timeout, this, qOverload<>(&VolumeView::update));
}

VolumeView::~VolumeView() {
    makeCurrent();
    gpu_.reset();
    doneCurrent();
    fused_.reset();
    scene_.reset();
}

bool VolumeView::hasVolume() const { return scene_ != nullptr; }

void VolumeView::setTransferFunction(const core::TransferFunction& tf) {
    tf_ = std::make_unique<core::TransferFunction>(tf);
    straightTf_.reset();
    if (tf.hasRefraction()) {
        straightTf_ = std::make_unique<core::TransferFunction>(tf);
        straightTf_->setRefraction({});
    }
    for (auto& scene : times_)  // what the neighbours need changes with what shows
        if (scene) scene->prefetchedFor.reset();
    update();
}

void VolumeView::setRenderSettings(const core::RenderSettings& settings) {
    settings_ = settings;
    if (scene_) volume_view::applyMode(scene_->ws.options(), settings);
    if (split_) volume_view::applyMode(split_->ws.options(), settings);
    for (auto& scene : times_)
        if (scene) scene->prefetchedFor.reset();
    for (auto& scene : times_)
        if (scene) volume_view::applyMode(scene->ws.options(), settings);
    update();
}

void VolumeView::setTools(const core::ToolSet& tools) {
    tools.validate();
    settings_.tools = tools;
    update();
}

void VolumeView::setAccuracy(double voxelsPerPixel) {
    accuracy_ = std::clamp(voxelsPerPixel, 0.25, 16.0);
    if (scene_) scene_->ws.options().voxelsPerPixel = accuracy_;
    if (fused_) fused_->ws.options().voxelsPerPixel = accuracy_;
    if (split_) split_->ws.options().voxelsPerPixel = accuracy_;
    for (auto& scene : times_)
        if (scene) {
            scene->ws.options().voxelsPerPixel = accuracy_;
            scene->prefetchedFor.reset();
        }
    update();
}

void VolumeView::setStandardView(core::OrbitCamera::Standard view) {
    camera_.setStandard(view);
    update();
}

void VolumeView::resetView() {
    if (scene_) {
        const auto& s = scene_->space;
        const glm::dvec3 centre = s.centre();
        const glm::dvec3 corner(s.octreeToPatient * glm::dvec4(0, 0, 0, 1.0));
        camera_.frame(centre, glm::length(centre - corner));
    }
    camera_.setStandard(core::OrbitCamera::Standard::Anterior);
    update();
}

QString VolumeView::levelReadout() const {
    if (!scene_) return {};
    if (!refractionOff_.isEmpty()) return levelOnlyReadout() + QStringLiteral(" \u2022 ") + refractionOff_;
    return levelOnlyReadout();
}

QString VolumeView::levelOnlyReadout() const {
    const auto& r = readouts_;
    const QString range = r.finestLevel == r.coarsestLevel ? tr("level %1").arg(r.finestLevel)
                                                           : tr("levels %1\u2013%2").arg(r.finestLevel).arg(r.coarsestLevel);
    QString of = tr("%1 of %2").arg(range).arg(r.levels - 1);
    if (splitShown_) {  // level l holds cells of N·2^l voxels
        const int n = int(split_->reader->header().split.n);
        const int fine = n << r.finestLevel, coarse = n << r.coarsestLevel;
        of = fine == coarse ? tr("split-voxels, cells of %1 voxels").arg(fine)
                            : tr("split-voxels, cells of %1\u2013%2 voxels").arg(fine).arg(coarse);
        if (r.settled && r.complete) return of;
    }
    if (!r.settled) return tr("%1, refining\u2026").arg(of);
    if (!r.complete) return tr("%1: the brick budget is reached").arg(of);
    if (r.coarsestLevel == 0) return tr("full resolution");
    return tr("%1, as fine as the pixels show").arg(of);
}

QStringList VolumeView::orientationLabels() const {
    // Without a known orientation the letters would be a guess: "?" instead (left is never right).
    if (scene_ && scene_->reader->geometry().orientationAssumed) return {"?", "?", "?", "?"};
    return {QString::fromStdString(core::OrbitCamera::patientLabel(-camera_.right())),
            QString::fromStdString(core::OrbitCamera::patientLabel(camera_.right())),
            QString::fromStdString(core::OrbitCamera::patientLabel(camera_.up())),
            QString::fromStdString(core::OrbitCamera::patientLabel(-camera_.up()))};
}

void VolumeView::initializeGL() {
    if (const auto* r = glGetString(GL_RENDERER)) {
        const auto* v = glGetString(GL_VERSION);
        glRenderer_ = QStringLiteral("%1, %2").arg(QString::fromLatin1(reinterpret_cast<const char*>(r)),
                                                  v ? QString::fromLatin1(reinterpret_cast<const char*>(v)) : QString());
    }
    try {
        gpu_ = std::make_unique<render::GpuRayCaster>();
    } catch (const std::exception& e) {
        error_ = QString::fromStdString(e.what());
    }
}

core::RenderImage VolumeView::renderFrame(const core::View& view, const core::RenderSettings& rs, bool converge) {
    // A fused volume is marched with the open one in DVR without tools; otherwise the open volume
    // alone, as split-voxels when it has them (DVR).
    const bool dvr = rs.mode == core::RenderSettings::Mode::Dvr;
    fusedShown_ = fused_ && fusedTf_ && dvr && !rs.tools.variantBits();
    splitShown_ = split_ && dvr && !fusedShown_;
    if (splitShown_) {  // what the crop box and the clip plane remove is not loaded either
        split_->ws.options().takeCullingOf(scene_->ws.options());
    }
    const auto& tf = drawnTf(rs, fusedShown_, splitShown_);
    auto& ws = drawn().ws;
    ws.converge({view}, tf, {}, converge ? 64 : 1);
    std::optional<render::GpuRayCaster::Overlay> overlay;
    if (fusedShown_) {
        fused_->ws.options().crop = {};
        fused_->ws.converge({view}, *fusedTf_, {}, converge ? 64 : 1);
        overlay.emplace(render::GpuRayCaster::Overlay{*fused_->reader, fused_->ws.index(), fused_->ws.slotBricks(), *fusedTf_});
    }
    auto img = gpu_->render(*drawn().reader, ws.index(), ws.slotBricks(), tf, rs, view, overlay ? &*overlay : nullptr);
    if (fusedShown_ && rs.countRays) fused_->ws.setRayCounts(img.overlayRayCounts);
    // Leave the GL state as QPainter's engine expects it.
    glUseProgram(0);
    glBindTextureUnit(0, 0);
    glBindTextureUnit(1, 0);
    glBindTextureUnit(2, 0);
    return img;
}

const core::TransferFunction& VolumeView::drawnTf(const core::RenderSettings& rs, bool fused, bool split) {
    refractionOff_.clear();
    if (!straightTf_) return *tf_;
    if (rs.mode != core::RenderSettings::Mode::Dvr) refractionOff_ = tr("refraction is drawn in DVR");
    else if (rs.tools.variantBits()) refractionOff_ = tr("refraction is off while the tools are on");
    else if (fused) refractionOff_ = tr("refraction is off with a fused volume");
    else if (split) refractionOff_ = tr("refraction is off with split-voxels");
    return refractionOff_.isEmpty() ? *tf_ : *straightTf_;
}

void VolumeView::setFrameReconstruction(bool on) {
    if (on == frameReconstruction()) return;
    auto options = quality_.options();
    options.subFrames = on;
    quality_.setOptions(options);
    rebuilt_.reset();
}

core::RenderImage VolumeView::rebuildFrame(core::RenderImage subFrame, int k) {
    // A new number whenever the picture may differ: another camera or size, or bricks that
    // changed the cut (the rebuilt image keeps a sub-frame's pixels only within one picture).
    if (!lastView_.sameCamera(rebuiltFor_) || drawn().ws.stats().uploads > 0) ++rebuiltPicture_;
    rebuiltFor_ = lastView_;
    auto counts = std::move(subFrame.rayCounts);
    core::RenderImage out = rebuilt_.add(subFrame, k, rebuiltPicture_);
    out.rayCounts = std::move(counts);
    return out;
}

void VolumeView::paintGL() {
    QPainter painter(this);
    painter.fillRect(rect(), Qt::black);
    const int w = int(width() * devicePixelRatioF()), h = int(height() * devicePixelRatioF());
    if (scene_ && tf_ && gpu_ && error_.isEmpty()) {
        painter.beginNativePainting();
        try {
            const bool moving = dragging_ || settle_.isActive();
            const auto level = quality_.next(moving);
            core::RenderSettings rs = settings_;
            rs.stepScale *= level.stepScale;
            rs.countRays = true;
            if (level.subFrame) rs.subFrame = rebuilt_.next();
            const auto view = camera_.view(w, h);
            // A clip plane seen face-on hides its far side: those bricks are not even loaded.
            scene_->ws.options().clip = settings_.mode == core::RenderSettings::Mode::Dvr && settings_.tools.clipHides(view);
            scene_->ws.options().clipPlane = settings_.tools.keptHalfSpace();
            scene_->ws.options().crop = settings_.crop;  // what the crop box removes is not loaded
            QElapsedTimer t;
            t.start();
            lastView_ = view.scaled(level.resolution);
            auto img = renderFrame(lastView_, rs, false);
            if (level.subFrame) img = rebuildFrame(std::move(img), rs.subFrame);
            lastDepth_ = img.depth;
            // The cut was refined for the reduced view; refine it for the full one next frame.
            drawn().ws.setRayCounts(img.rayCounts);
            prefetchNeighbours();
            const double ms = double(t.nsecsElapsed()) / 1e6;
            quality_.frameDone(level, ms);
            frame_ = toQImage(img).scaled(w, h, Qt::IgnoreAspectRatio, Qt::SmoothTransformation);
            ++frames_;
            const auto& st = drawn().ws.stats();
            readouts_.frameMs = ms;
            readouts_.fps = 1000.0 / std::max(ms, 1e-3);
            readouts_.residentBricks = st.cutNodes;
            readouts_.poolSlots = st.slotsUsed;
            readouts_.cacheBytes = drawn().cache.bytes();
            readouts_.cacheBudget = drawn().cache.budget();
            readouts_.resolution = level.resolution;
            readouts_.subFrame = level.subFrame;
            readouts_.complete = st.complete;
            readouts_.settled = st.settled();
            readouts_.finestLevel = st.finestLevel;
            readouts_.coarsestLevel = st.coarsestLevel;
            readouts_.levels = drawn().reader->levelCount();
            // Keep drawing while bricks arrive or the frame is not yet full quality, but never
            // forever: a cut that cannot settle (pool too small for the view) stops after a while.
            const bool settled = st.settled() && (!fusedShown_ || fused_->ws.stats().settled());
            unsettledFrames_ = settled ? 0 : unsettledFrames_ + 1;
            if ((!settled && unsettledFrames_ < 400) || !level.full()) refine_.start();
        } catch (const std::exception& e) {
            error_ = QString::fromStdString(e.what());
            emit failed(error_);
        }
        painter.endNativePainting();
        if (!frame_.isNull()) painter.drawImage(rect(), frame_);
    }
    paintOverlays(painter);
    painter.end();
    if (scene_ && error_.isEmpty()) emit frameRendered();
}

void VolumeView::paintOverlays(QPainter& p) {
    p.setRenderHint(QPainter::Antialiasing);
    if (!error_.isEmpty()) {
        p.setPen(QColor(255, 120, 100));
        p.drawText(rect().adjusted(12, 12, -12, -12), Qt::AlignCenter | Qt::TextWordWrap, error_);
        return;
    }
    if (!scene_) {
        p.setPen(QColor(170, 170, 170));
        p.drawText(rect(), Qt::AlignCenter, tr("Open a series from the study browser, or File \u2192 Open"));
        return;
    }
    // Patient-orientation labels at the edges.
    p.setFont(font());
    drawEdgeLabels(p, rect().adjusted(8, 6, -8, -6), orientationLabels(), 1.4);
    drawAssumedGeometry(p, rect().adjusted(8, 30, -8, -6), scene_->reader->geometry());
    // Which octree levels the frame shows (level 0 is full resolution), bottom right.
    QFont readoutFont = font();
    readoutFont.setPointSizeF(readoutFont.pointSizeF() * 0.85);
    p.setFont(readoutFont);
    p.setPen(QColor(200, 200, 200));
    p.drawText(rect().adjusted(8, 6, -8, -6), Qt::AlignBottom | Qt::AlignRight, levelReadout());
    // Orientation cube (bottom left): faces towards the viewer, lettered in patient terms.
    const double s = 26.0;
    const QPointF c(14 + s * 1.3, height() - 14 - s * 1.3);
    auto cubePoint = [&](const glm::dvec3& v) {
        return c + QPointF(glm::dot(v, camera_.right()) * s, -glm::dot(v, camera_.up()) * s);
    };
    struct Face {
        glm::dvec3 n;
        const char* letter;
    };
    const Face faces[] = {{{1, 0, 0}, "L"}, {{-1, 0, 0}, "R"}, {{0, 1, 0}, "P"},
                          {{0, -1, 0}, "A"}, {{0, 0, 1}, "S"}, {{0, 0, -1}, "I"}};
    QFont small = font();
    small.setBold(true);
    p.setFont(small);
    for (const auto& face : faces) {
        const double facing = glm::dot(face.n, camera_.back());
        if (facing <= 0.05) continue;
        glm::dvec3 a = glm::abs(face.n.x) > 0 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
        glm::dvec3 b = glm::cross(face.n, a);
        QPainterPath path;
        path.moveTo(cubePoint(face.n + a + b));
        path.lineTo(cubePoint(face.n + a - b));
        path.lineTo(cubePoint(face.n - a - b));
        path.lineTo(cubePoint(face.n - a + b));
        path.closeSubpath();
        const int shade = int(70 + 120 * facing);
        p.fillPath(path, QColor(shade / 2, shade / 2, shade));
        p.setPen(QColor(220, 220, 220));
        p.drawPath(path);
        const QPointF centre = cubePoint(face.n);
        p.drawText(QRectF(centre.x() - 10, centre.y() - 10, 20, 20), Qt::AlignCenter,
                   scene_->reader->geometry().orientationAssumed ? "?" : face.letter);
    }
    // Probe handles: the centre and the outline of the focal and context probes.
    const auto& tools = settings_.tools;
    auto handle = [&](const glm::dvec3& probeCentre, double radius, const QColor& colour) {
        QPointF at;
        double depth = 0;
        if (!project(probeCentre, at, depth)) return;
        const double px = radius / depth / std::tan(glm::radians(camera_.fovYDegrees()) / 2.0) * height() / 2.0;
        p.setPen(QPen(colour, 1.5, Qt::DashLine));
        p.setBrush(Qt::NoBrush);
        p.drawEllipse(at, px, px);
        p.setPen(QPen(colour, 2));
        p.drawLine(at - QPointF(6, 0), at + QPointF(6, 0));
        p.drawLine(at - QPointF(0, 6), at + QPointF(0, 6));
    };
    if (tools.focal.enabled) handle(tools.focal.centre, std::max({tools.focal.radii.x, tools.focal.radii.y, tools.focal.radii.z}), QColor(120, 220, 255));
    if (tools.context.enabled) handle(tools.context.centre, tools.context.radius, QColor(255, 170, 90));
    // Distances measured in this view, and the end picked of the one being measured.
    MeasurementOverlay overlay(
        p, size(),
        [this](const glm::dvec3& x) { return projected(x).value_or(QPointF(-1e6, -1e6)); },
        [](const glm::dvec3&) { return true; }, -camera_.back(), 1.0);
    overlay.setSpacingAssumed(scene_ && scene_->reader->geometry().spacingAssumed);
    overlay.list(measurements_);
    for (const auto& x : picked_) overlay.distance(x, x, {});
    if (const auto crop = cropHandlesNow()) crop->paint(p, settings_.crop);
    // Spheres: their outline as seen (a circle of their radius about the projected centre).
    for (const auto& m : measurements_) {
        if (!m.region || m.region->kind != core::MeasureRegion::Kind::Sphere) continue;
        const auto centre = projected(m.region->centre);
        const auto rim = projected(m.region->centre + m.region->radius * camera_.right());
        if (centre && rim)
            overlay.sphere(*centre, std::hypot(rim->x() - centre->x(), rim->y() - centre->y()),
                           MeasurementOverlay::regionLabel(m));
    }
}

}  // namespace hvx::ui
