// epoxy first: it must precede any desktop GL header (Qt's included).
#include <epoxy/gl.h>

#include "ui/VolumeView.h"

#include <QSurfaceFormat>

#include <QKeyEvent>
#include <QMouseEvent>
#include <QNativeGestureEvent>
#include <QPainter>
#include <QPainterPath>
#include <QWheelEvent>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/trigonometric.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/ContentBox.h"
#include "core/base/Error.h"
#include "core/image/ImageWriter.h"
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

void VolumeView::editTools(const core::ToolSet& tools) {
    settings_.tools = tools;
    emit toolsEdited(tools);
    interacted();
}

void VolumeView::interacted() {
    settle_.start();
    update();
}

void VolumeView::mousePressEvent(QMouseEvent* e) {
    lastPos_ = e->position().toPoint();
    if (picking_ != Picking::None && e->button() == Qt::LeftButton) {  // D or B: a point on the surface
        const bool sphere = picking_ == Picking::Sphere;
        const QString what = sphere ? tr("Sphere") : tr("Distance");
        const auto at = surfaceAt(e->position());
        if (!at) {
            emit hint(tr("%1: nothing under the cursor; click on the volume (Esc cancels)").arg(what));
            return;
        }
        picked_.push_back(*at);
        if (picked_.size() == 2) {
            core::Measurement m;
            m.view = "3D";
            m.a = picked_[0];
            m.b = picked_[1];
            picking_ = Picking::None;
            picked_.clear();
            if (sphere) {
                m.kind = core::Measurement::Kind::Region;
                m.region = core::MeasureRegion::sphere(m.a, glm::length(m.b - m.a));
                try {
                    m.stats = core::RegionStatistics::compute(*scene_->reader, *m.region);
                    emit hint(tr("Sphere: radius %1 mm, %2 voxels").arg(m.region->radius, 0, 'f', 1).arg(m.stats->voxels));
                    emit measured(m);
                } catch (const std::exception& ex) {
                    emit hint(tr("Sphere not measured: %1").arg(QString::fromStdString(ex.what())));
                }
            } else {
                m.kind = core::Measurement::Kind::Distance;
                emit hint(tr("Distance: %1 mm").arg(m.lengthMm(), 0, 'f', 1));
                emit measured(m);
            }
        } else {
            emit hint(sphere ? tr("Sphere: click a point of its rim") : tr("Distance: click its other end"));
        }
        update();
        return;
    }
    if (const auto crop = cropHandlesNow(); crop && e->button() == Qt::LeftButton && e->modifiers() == Qt::NoModifier) {
        if ((cropFace_ = crop->faceAt(settings_.crop, e->position()))) {  // a crop box face's handle
            cropPress_ = settings_.crop;
            cropFrom_ = e->position();
            return;
        }
    }
    const bool modified = e->modifiers() & (Qt::ControlModifier | Qt::AltModifier);
    if (e->button() == Qt::LeftButton && modified) {  // tools: pick on release, or drag the probes
        toolDrag_.press(lastPos_);
        return;
    }
    dragging_ = true;
    dragButton_ = e->button();
}

bool VolumeView::project(const glm::dvec3& p, QPointF& out, double& depth) const {
    const auto v = camera_.view(width(), height());
    const glm::dvec3 rel = p - v.eye;
    depth = -glm::dot(rel, camera_.back());
    if (depth <= 1e-6) return false;
    const double t = std::tan(glm::radians(v.fovYDegrees) / 2.0);
    const double nx = glm::dot(rel, camera_.right()) / depth / (t * double(width()) / height());
    const double ny = glm::dot(rel, camera_.up()) / depth / t;
    out = QPointF((nx + 1.0) / 2.0 * width(), (1.0 - ny) / 2.0 * height());
    return true;
}

std::optional<QPointF> VolumeView::projected(const glm::dvec3& p) const {
    QPointF at;
    double depth = 0;
    if (!project(p, at, depth)) return std::nullopt;
    return at;
}

void VolumeView::mouseMoveEvent(QMouseEvent* e) {
    const QPoint pos = e->position().toPoint();
    const QPoint d = pos - lastPos_;
    lastPos_ = pos;
    if (cropFace_) {
        if (const auto crop = cropHandlesNow()) emit cropDragged(crop->dragged(cropPress_, *cropFace_, cropFrom_, e->position()));
        return;
    }
    if (toolDrag_.active()) {  // Ctrl+drag moves the probes or the clip plane (ui/ToolDragger)
        if (auto tools = toolDrag_.move(pos, d, e->modifiers() & Qt::ShiftModifier, settings_.tools, camera_, width(),
                                        height()))
            editTools(*tools);
        return;
    }
    if (!dragging_) return;
    const bool pan = dragButton_ == Qt::MiddleButton || (dragButton_ == Qt::LeftButton && (e->modifiers() & Qt::ShiftModifier));
    if (pan) camera_.pan(d.x(), d.y(), height());
    else if (dragButton_ == Qt::RightButton) camera_.zoom(std::pow(1.005, -d.y()));
    else if (dragButton_ == Qt::LeftButton) camera_.rotate(d.x(), d.y(), height());
    update();
}

void VolumeView::mouseReleaseEvent(QMouseEvent* e) {
    cropFace_.reset();
    if (toolDrag_.release()) {
        if (const auto at = surfaceAt(e->position())) emit surfacePicked(*at, (e->modifiers() & Qt::AltModifier) != 0);
    }
    dragging_ = false;
    update();  // the next frame is full quality
}

std::optional<glm::dvec3> VolumeView::surfaceAt(QPointF pos) const {
    if (!scene_ || lastDepth_.empty()) return std::nullopt;
    const double sx = pos.x() / std::max(1, width()) * lastView_.width;
    const double sy = pos.y() / std::max(1, height()) * lastView_.height;
    const int px = std::clamp(int(sx), 0, lastView_.width - 1), py = std::clamp(int(sy), 0, lastView_.height - 1);
    const float depth = lastDepth_[std::size_t(py) * std::size_t(lastView_.width) + std::size_t(px)];
    if (!std::isfinite(depth)) return std::nullopt;
    glm::dvec3 o, d;
    lastView_.ray(px, py, o, d);
    return o + d * double(depth);
}

void VolumeView::requestGlFormat() {
    QSurfaceFormat format;
    format.setVersion(4, 5);
    format.setProfile(QSurfaceFormat::CoreProfile);
    QSurfaceFormat::setDefaultFormat(format);
}

void VolumeView::startDistance() {
    if (!scene_) return;
    picking_ = Picking::Distance;
    picked_.clear();
    emit hint(tr("Distance: click its first end on the volume (Esc cancels)"));
}

void VolumeView::setCropEditing(bool on) {
    cropEditing_ = on;
    update();
}

std::optional<CropBoxHandles> VolumeView::cropHandlesNow() const {
    if (!cropEditing_ || !scene_) return std::nullopt;
    return CropBoxHandles(
        scene_->space, scene_->reader->geometry().dims,
        [this](const glm::dvec3& x) { return projected(x); },
        [this](QPointF pos) {
            glm::dvec3 o, d;
            camera_.view(width(), height()).ray(pos.x() - 0.5, pos.y() - 0.5, o, d);  // (ray() takes pixel indices)
            return std::make_pair(o, d);
        });
}

std::vector<glm::dvec3> VolumeView::cropHandlePoints() const {
    std::vector<glm::dvec3> out;
    if (const auto crop = cropHandlesNow())
        for (int face = 0; face < 6; ++face) out.push_back(crop->faceCentre(settings_.crop, face));
    return out;
}

std::vector<QPointF> VolumeView::cropHandles() const {
    std::vector<QPointF> out;
    for (const auto& p : cropHandlePoints())
        if (const auto at = projected(p)) out.push_back(*at);
    return out;
}

void VolumeView::startSphere() {
    if (!scene_) return;
    picking_ = Picking::Sphere;
    picked_.clear();
    emit hint(tr("Sphere: click its centre on the volume (Esc cancels)"));
}

void VolumeView::setMeasurements(std::vector<core::Measurement> items) {
    measurements_.clear();
    for (auto& m : items)
        if (m.view == "3D") measurements_.push_back(std::move(m));
    update();
}

void VolumeView::wheelEvent(QWheelEvent* e) {
    const double steps = !e->pixelDelta().isNull() ? e->pixelDelta().y() / 60.0 : e->angleDelta().y() / 120.0;
    if (e->modifiers() & Qt::ControlModifier)  // Ctrl+wheel scales the probes
        if (auto tools = ToolDragger::scaled(settings_.tools, steps)) {
            editTools(*tools);
            return;
        }
    camera_.zoom(std::pow(1.1, steps));
    interacted();
}

bool VolumeView::event(QEvent* e) {
    if (e->type() == QEvent::NativeGesture) {  // touchpad pinch
        auto* g = static_cast<QNativeGestureEvent*>(e);
        if (g->gestureType() == Qt::ZoomNativeGesture) {
            camera_.zoom(1.0 + g->value());
            interacted();
            return true;
        }
    }
    return QOpenGLWidget::event(e);
}

void VolumeView::keyPressEvent(QKeyEvent* e) {
    using S = core::OrbitCamera::Standard;
    switch (e->key()) {
    case Qt::Key_A: camera_.setStandard(S::Anterior); break;
    case Qt::Key_P: camera_.setStandard(S::Posterior); break;
    case Qt::Key_L: camera_.setStandard(S::Left); break;
    case Qt::Key_R: camera_.setStandard(S::Right); break;
    case Qt::Key_S: camera_.setStandard(S::Superior); break;
    case Qt::Key_I: camera_.setStandard(S::Inferior); break;
    case Qt::Key_Home: resetView(); break;
    case Qt::Key_D: startDistance(); return;
    case Qt::Key_B: startSphere(); return;
    case Qt::Key_Escape:
        picking_ = Picking::None;
        picked_.clear();
        update();
        return;
    case Qt::Key_Left: camera_.rotate(-height() / 36.0, 0, height()); break;
    case Qt::Key_Right: camera_.rotate(height() / 36.0, 0, height()); break;
    case Qt::Key_Up: camera_.rotate(0, -height() / 36.0, height()); break;
    case Qt::Key_Down: camera_.rotate(0, height() / 36.0, height()); break;
    case Qt::Key_Plus:
    case Qt::Key_Equal: camera_.zoom(1.1); break;
    case Qt::Key_Minus: camera_.zoom(1.0 / 1.1); break;
    default: QOpenGLWidget::keyPressEvent(e); return;
    }
    interacted();
}

}  // namespace hvx::ui
