#include "render/GpuRayCaster.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/base/Error.h"
#include "core/image/FrameReconstructor.h"
#include "core/streaming/OctreeSpace.h"

namespace hvx::render {

namespace {
struct alignas(16) FrameBlock {  // std140 mirror of raycast_inputs.glsl
    glm::mat4 patientToOctree;
    glm::vec4 extent, tfRange, shading, extra, enhance;
    glm::uvec4 brick, image;
    glm::vec4 cropLo, cropHi;
    glm::mat4 patientToOctreeB;
    glm::vec4 extentB, tfRangeB;
    glm::uvec4 brickB, fusionB;
    glm::uvec4 pixels;
    glm::vec4 detail;
};
static_assert(sizeof(FrameBlock) == 64 + 5 * 16 + 2 * 16 + 2 * 16 + 64 + 6 * 16, "std140 layout of Frame");
struct ViewBlock {  // std430 mirror of raycast_inputs.glsl's ViewCamera
    glm::vec4 eye, forward, right, up, screenCentre, screenRight, screenUp, screenViewer, screenProjector;
};
static_assert(sizeof(ViewBlock) == 9 * 16, "std430 layout of ViewCamera");
}  // namespace

GpuRayCaster::GpuRayCaster(PoolPrecision precision) {
    glCreateBuffers(kBuffers, buffers_);
    if (precision == PoolPrecision::Auto) {
        const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        const std::string name = renderer ? renderer : "";
        floatPool_ = name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos;
    } else {
        floatPool_ = precision == PoolPrecision::Float;
    }
}

GpuRayCaster::~GpuRayCaster() {
    glDeleteBuffers(kBuffers, buffers_);
    for (auto& pool : pools_)
        if (pool.texture) glDeleteTextures(1, &pool.texture);
}

namespace {
/// The pool's texture format for a volume's stored type: its own precision, never more.
GLenum poolFormat(core::ScalarType type) {
    switch (type) {
    case core::ScalarType::UInt8: return GL_R8;
    case core::ScalarType::Int16:
    case core::ScalarType::UInt16: return GL_R16;
    case core::ScalarType::Float32: break;
    }
    return GL_R32F;
}
/// What the visible cells depend on: the transfer function's extinction over its range, the
/// mode and the iso value (FNV-1a; 0 stands for "no skipping").
std::uint64_t cellKey(const core::TransferFunction& tf, const core::RenderSettings& settings) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
    };
    for (const auto& F : tf.integralTable()) mix(&F.w, sizeof F.w);
    // An index ≠ 1 makes a transparent cell content (TransferFunction::isEmpty).
    for (const auto& N : tf.refractionTable()) mix(&N.y, sizeof N.y);
    const double range[3] = {tf.valueMin(), tf.valueMax(), settings.isoValue};
    mix(range, sizeof range);
    const int mode = int(settings.mode);
    mix(&mode, sizeof mode);
    return h | 1u;
}
}  // namespace

std::size_t GpuRayCaster::uploadPool(Pool& pool, const std::vector<std::shared_ptr<const core::Brick>>& slots,
                                     std::uint32_t brickSize, std::uint32_t border, core::ScalarType type, bool split) {
    const std::uint32_t edge = brickSize + 2 * border;
    std::size_t uploaded = 0;
    const auto count = std::uint32_t(std::max<std::size_t>(1, slots.size()));
    // A near-cubic grid of slots, rebuilt only when it must grow or the volume's type changes.
    if (!pool.texture || edge != pool.edge || type != pool.type || split != pool.split ||
        count > pool.row * pool.row * pool.layers) {
        if (pool.texture) glDeleteTextures(1, &pool.texture);
        GLint maxSize = 2048;
        glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSize);
        const auto perAxis = std::uint32_t(maxSize) / edge;
        pool.row = std::min(perAxis, std::max(1u, std::uint32_t(std::ceil(std::cbrt(double(count) * 1.25)))));
        pool.layers = (count + pool.row * pool.row - 1) / (pool.row * pool.row);
        if (pool.layers > perAxis) throw core::Error("the brick pool does not fit in a 3D texture");
        pool.layer = pool.row * pool.row;
        pool.edge = edge;
        pool.type = type;
        glCreateTextures(GL_TEXTURE_3D, 1, &pool.texture);
        pool.split = split;
        // Split-voxel cells are integers read texel by texel (an integer texture is never filtered).
        glTextureStorage3D(pool.texture, 1, split ? GL_RGBA16UI : poolFormat(type), GLsizei(pool.row * edge),
                           GLsizei(pool.row * edge), GLsizei(pool.layers * edge));
        glTextureParameteri(pool.texture, GL_TEXTURE_MIN_FILTER, split ? GL_NEAREST : GL_LINEAR);
        glTextureParameteri(pool.texture, GL_TEXTURE_MAG_FILTER, split ? GL_NEAREST : GL_LINEAR);
        glTextureParameteri(pool.texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(pool.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTextureParameteri(pool.texture, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
        pool.content.assign(pool.row * pool.row * pool.layers, nullptr);
        pool.records.assign(pool.content.size(), {});
        pool.cells.assign(pool.content.size(), {});
        pool.cellsStale.assign(pool.content.size(), true);
        pool.bytes = pool.content.size() * std::size_t(edge) * edge * edge * (split ? 8 : core::scalarSize(type));
    }
    std::vector<std::uint16_t> biased;
    for (std::size_t s = 0; s < slots.size(); ++s) {
        const auto& brick = slots[s];
        if (!brick || pool.content[s] == brick) continue;  // unchanged since the last upload
        if (brick->edge != edge) throw core::Error("a brick does not match the pool's slot size");
        if (brick->splitVoxels != split) throw core::Error("a brick does not match the pool's kind (split-voxel or not)");
        if (split) {
            uploadSplitBrick(pool, std::uint32_t(s), *brick, biased);
            pool.content[s] = brick;
            pool.cells[s] = core::BrickCells::ofSplit(*brick);
            pool.cellsStale[s] = true;
            uploaded += brick->data.size();
            continue;
        }
        // The texel format converts to normalised floats; the slot's affine map gives stored values back.
        GLenum format = GL_FLOAT;
        const void* data = brick->data.data();
        float scale = 1.0f, offset = 0.0f;
        if (brick->lossy8) {
            format = GL_UNSIGNED_BYTE;
            scale = brick->quantMax - brick->quantMin;
            offset = brick->quantMin;
        } else if (brick->type == core::ScalarType::UInt8) {
            format = GL_UNSIGNED_BYTE;
            scale = 255.0f;
        } else if (brick->type == core::ScalarType::UInt16) {
            format = GL_UNSIGNED_SHORT;
            scale = 65535.0f;
        } else if (brick->type == core::ScalarType::Int16) {
            // Biased to unsigned so that -32768 (often the padding value) stays exact; a signed
            // normalised format would clamp it to -32767.
            const auto* v = brick->as<std::int16_t>();
            biased.resize(brick->data.size() / 2);
            for (std::size_t i = 0; i < biased.size(); ++i) biased[i] = std::uint16_t(std::int32_t(v[i]) + 32768);
            format = GL_UNSIGNED_SHORT;
            data = biased.data();
            scale = 65535.0f;
            offset = -32768.0f;
        }
        const auto slot = std::uint32_t(s);
        glTextureSubImage3D(pool.texture, 0, GLint(slot % pool.row * edge), GLint(slot / pool.row % pool.row * edge),
                            GLint(slot / pool.layer * edge), GLsizei(edge), GLsizei(edge), GLsizei(edge), GL_RED,
                            format, data);
        pool.content[s] = brick;
        pool.cells[s] = core::BrickCells::of(*brick, brickSize, border);
        pool.cellsStale[s] = true;
        pool.records[s].decode = glm::vec2(scale, offset);
        uploaded += brick->data.size();
    }
    return uploaded;
}

void GpuRayCaster::uploadSplitBrick(Pool& pool, std::uint32_t slot, const core::Brick& brick,
                                    std::vector<std::uint16_t>& scratch) {
    // One RGBA16UI texel per cell: 16-bit data is uploaded as encoded (two values, then the
    // plane's four bytes); 8-bit data's six bytes are widened to the same four channels.
    const std::uint32_t edge = pool.edge;
    const std::size_t cells = std::size_t(edge) * edge * edge;
    const void* data = brick.data.data();
    if (core::scalarSize(brick.type) == 1) {
        if (brick.data.size() != cells * 6) throw core::Error("a split-voxel brick has the wrong size");
        const auto* in = reinterpret_cast<const std::uint8_t*>(brick.data.data());
        scratch.resize(cells * 4);
        for (std::size_t i = 0; i < cells; ++i, in += 6) {
            scratch[4 * i] = in[0];
            scratch[4 * i + 1] = in[1];
            scratch[4 * i + 2] = std::uint16_t(in[2] | in[3] << 8);
            scratch[4 * i + 3] = std::uint16_t(in[4] | in[5] << 8);
        }
        data = scratch.data();
    } else if (brick.data.size() != cells * 8) {
        throw core::Error("a split-voxel brick has the wrong size");
    }
    glTextureSubImage3D(pool.texture, 0, GLint(slot % pool.row * edge), GLint(slot / pool.row % pool.row * edge),
                        GLint(slot / pool.layer * edge), GLsizei(edge), GLsizei(edge), GLsizei(edge), GL_RGBA_INTEGER,
                        GL_UNSIGNED_SHORT, data);
}

void GpuRayCaster::updateVisibleCells(Pool& pool, const std::vector<std::shared_ptr<const core::Brick>>& slots,
                                      const core::TransferFunction& tf, const core::RenderSettings& settings, bool skip,
                                      bool labels) {
    const bool dvr = settings.mode == core::RenderSettings::Mode::Dvr;
    const std::uint64_t key = skip ? cellKey(tf, settings) : 0;
    if (key != pool.cellKey) std::fill(pool.cellsStale.begin(), pool.cellsStale.end(), true);
    pool.cellKey = key;
    for (std::size_t s = 0; s < slots.size(); ++s) {
        if (!slots[s] || !pool.cellsStale[s]) continue;
        // A split-voxel label map's values are classified by their own entry: nothing to widen.
        const std::uint64_t bits = !skip ? ~std::uint64_t(0)
                                   : dvr ? pool.cells[s].visible(tf, pool.split && labels)
                                         : pool.cells[s].straddling(settings.isoValue);
        pool.records[s].visible = glm::uvec2(std::uint32_t(bits), std::uint32_t(bits >> 32));
        pool.cellsStale[s] = false;
    }
}

core::RenderImage GpuRayCaster::render(const core::OctreeReader& reader, const core::SpatialIndex& index,
                                       const std::vector<std::shared_ptr<const core::Brick>>& slots,
                                       const core::TransferFunction& tf, const core::RenderSettings& settings,
                                       const core::View& view, const Overlay* overlay) {
    return std::move(renderViews(reader, index, slots, tf, settings, {view}, overlay).front());
}

namespace {
/// Fills a buffer with the first volume's array followed by the second's (fusion), or the first's alone.
template <class T>
void uploadPair(unsigned buffer, const std::vector<T>& first, const std::vector<T>* second) {
    const std::size_t a = first.size() * sizeof(T), b = second ? second->size() * sizeof(T) : 0;
    glNamedBufferData(buffer, GLsizeiptr(std::max<std::size_t>(a + b, 16)), nullptr, GL_STREAM_DRAW);
    if (a) glNamedBufferSubData(buffer, 0, GLsizeiptr(a), first.data());
    if (b) glNamedBufferSubData(buffer, GLintptr(a), GLsizeiptr(b), second->data());
}
/// A transfer function's tables as the shader reads them: f, F, and (F.w, f.w) per entry.
struct TfTables {
    std::vector<glm::vec4> table, integral;
    std::vector<glm::vec2> opacity;
    explicit TfTables(const core::TransferFunction& tf)
        : table(tf.table().begin(), tf.table().end()), integral(tf.integralTable().begin(), tf.integralTable().end()),
          opacity(integral.size()) {
        for (std::size_t i = 0; i < opacity.size(); ++i) opacity[i] = {integral[i].w, i < table.size() ? table[i].w : 0.0f};
    }
};
}  // namespace

std::vector<core::RenderImage> GpuRayCaster::renderViews(const core::OctreeReader& reader, const core::SpatialIndex& index,
                                                         const std::vector<std::shared_ptr<const core::Brick>>& slots,
                                                         const core::TransferFunction& tf,
                                                         const core::RenderSettings& settings,
                                                         const std::vector<core::View>& views, const Overlay* overlay) {
    if (views.empty()) return {};
    const int width = views.front().width, height = views.front().height;
    for (const auto& v : views)
        if (v.width != width || v.height != height) throw core::Error("a batch of views must share one image size");
    const int mode = int(settings.mode);
    const int tools = settings.mode == core::RenderSettings::Mode::Dvr ? settings.tools.variantBits() : 0;
    if (tools) settings.tools.validate();
    if (overlay && settings.mode != core::RenderSettings::Mode::Dvr)
        throw core::Error("two volumes are fused in 3D in DVR only");
    if (overlay && tools) throw core::Error("the illustrative tools are not drawn over a fused volume");
    // A split-voxel octree (1; 2 for signed values) is walked cell by cell (raycast_split.glsl).
    const int split = reader.splitVoxels() ? (reader.geometry().scalarType == core::ScalarType::Int16 ? 2 : 1) : 0;
    if (split && (settings.mode != core::RenderSettings::Mode::Dvr || overlay || tf.hasGradientOpacity()))
        throw core::Error(reader.path() + ": a split-voxel octree is drawn in DVR, alone, without gradient opacity");
    // Refraction (raycast_refract.glsl): DVR alone, with the enhancers and shading of the plain
    // march but not the tools, a fused volume or split-voxels.
    const int refract = settings.mode == core::RenderSettings::Mode::Dvr && tf.hasRefraction() ? 1 : 0;
    if (refract && (tools || overlay || split))
        throw core::Error("refraction is drawn without the illustrative tools, a fused volume or split-voxels");
    const int labels = reader.geometry().isLabel ? 1 : 0;
    const int fusion = overlay ? 1 + (overlay->reader.geometry().isLabel ? 1 : 0) : 0;  // 1 image, 2 label map
    // Gradient opacity: either volume's own curve, in the plain march or the fused one.
    const int gradient = settings.mode == core::RenderSettings::Mode::Dvr &&
                                 (tf.hasGradientOpacity() || (overlay && overlay->tf.hasGradientOpacity()))
                             ? 1
                             : 0;
    // A static variant per mode, tools, labels, fusion, gradient opacity and split-voxels.
    const int nearest = settings.nearest && !split ? 1 : 0;
    const int detail = settings.detailShading() && !tools && !overlay && !split ? 1 : 0;
    // Multilevel sampling (core::RenderSettings::multilevel) where some leaf blends with its
    // parent; with none, the plain variant draws the same image (+30 % a frame spared on llvmpipe).
    // The variant's level: how far up the field reaches (1 the parent, 2 the grandparent, 3 any).
    const int multilevel = settings.multilevel && !labels && !nearest && !split && !overlay && index.blendingLeaves > 0
                               ? int(std::clamp(index.levelReach, 1u, 3u))
                               : 0;
    // The detail shading's coarser gradient from the parent level, where the index links leaves to parents.
    const int detailParent = detail && !index.levels.empty() ? 1 : 0;
    auto& program = programs_[2 * (mode + 8 * tools) + labels + 4096 * fusion + 16384 * gradient + 32768 * split +
                              131072 * nearest + 262144 * detail + 524288 * refract + 1048576 * multilevel +
                              4194304 * detailParent];
    if (!program)
        program = std::make_unique<ComputeProgram>(
            ShaderLibrary::embedded(), "raycast.comp.glsl",
            std::vector<std::string>{"MODE " + std::to_string(mode), "HVX_TOOLS " + std::to_string(tools),
                                     "HVX_LABELS " + std::to_string(labels),
                                     "HVX_FUSION " + std::to_string(fusion ? 1 : 0),
                                     "HVX_LABELS_B " + std::to_string(fusion == 2 ? 1 : 0),
                                     "HVX_GRADIENT_OPACITY " + std::to_string(gradient),
                                     "HVX_SPLIT " + std::to_string(split ? 1 : 0),
                                     "HVX_SPLIT_SIGNED " + std::to_string(split == 2 ? 1 : 0),
                                     "HVX_NEAREST " + std::to_string(nearest), "HVX_DETAIL " + std::to_string(detail),
                                     "HVX_REFRACT " + std::to_string(refract),
                                     "HVX_MULTILEVEL " + std::to_string(multilevel),
                                     "HVX_DETAIL_PARENT " + std::to_string(detailParent)});
    if (refract)
        glNamedBufferData(buffers_[13], GLsizeiptr(tf.refractionTable().size() * sizeof(glm::vec2)),
                          tf.refractionTable().data(), GL_STREAM_DRAW);
    const auto packed = core::packTools(settings.tools, {settings.ambient, settings.diffuse, settings.specular, settings.shininess});
    static_assert(sizeof(packed) == 16 * 16, "std140 layout of HvxTools");
    glNamedBufferData(buffers_[9], sizeof packed, &packed, GL_STREAM_DRAW);
    uploaded_ = uploadPool(pools_[0], slots, reader.brickSize(), reader.border(),
                           floatPool_ && !split ? core::ScalarType::Float32 : reader.geometry().scalarType, split != 0);
    // Which cells of each slot's brick may show (64 bits per slot), kept from frame to frame.
    // The fused march skips each volume's cells under its own transfer function.
    const bool dvr = settings.mode == core::RenderSettings::Mode::Dvr;
    const bool skip = settings.skipEmptyCells && (dvr || settings.mode == core::RenderSettings::Mode::Iso);
    updateVisibleCells(pools_[0], slots, tf, settings, skip, reader.geometry().isLabel);
    if (overlay) {
        const auto& og = overlay->reader.geometry();
        uploaded_ += uploadPool(pools_[1], overlay->bricks, overlay->reader.brickSize(), overlay->reader.border(),
                                floatPool_ ? core::ScalarType::Float32 : og.scalarType);
        updateVisibleCells(pools_[1], overlay->bricks, overlay->tf, settings, skip, og.isLabel);
    }
    static_assert(sizeof(SlotRecord) == 16, "std430 layout of SlotRecord");
    uploadPair(buffers_[8], pools_[0].records, overlay ? &pools_[1].records : nullptr);
    // A base volume with no cut yet is one empty leaf, so that the overlay's nodes keep their place.
    static const core::SpatialIndex emptyLeaf = [] {
        core::SpatialIndex e;
        e.nodes.push_back({core::SpatialIndex::kNone, core::SpatialIndex::kLeafBit, core::SpatialIndex::kNone,
                           core::SpatialIndex::kNone});
        e.ropes.assign(6, core::SpatialIndex::kNone);
        return e;
    }();
    const core::SpatialIndex& base = overlay && index.nodes.empty() ? emptyLeaf : index;
    uploadPair(buffers_[0], base.nodes, overlay ? &overlay->index.nodes : nullptr);
    uploadPair(buffers_[1], base.ropes, overlay ? &overlay->index.ropes : nullptr);
    // The transfer functions' own tables (128 KiB each), uploaded every frame: cheap, and never
    // stale. Opacity alone, (F.w, f.w) per entry in one 8-byte read: most samples stop at the
    // opacity test.
    const TfTables tables(tf);
    const std::unique_ptr<TfTables> tablesB = overlay ? std::make_unique<TfTables>(overlay->tf) : nullptr;
    uploadPair(buffers_[2], tables.table, tablesB ? &tablesB->table : nullptr);
    uploadPair(buffers_[3], tables.integral, tablesB ? &tablesB->integral : nullptr);
    uploadPair(buffers_[11], tables.opacity, tablesB ? &tablesB->opacity : nullptr);
    if (gradient) {  // each volume's gradient table (the second's entries follow the first's); none: ones, unread
        const std::vector<float> none(core::TransferFunction::kGradientEntries, 1.0f);
        const auto& ga = tf.hasGradientOpacity() ? tf.gradientTable() : none;
        const auto* gb = overlay ? (overlay->tf.hasGradientOpacity() ? &overlay->tf.gradientTable() : &none) : nullptr;
        uploadPair(buffers_[12], ga, gb);
    }
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const std::size_t all = pixels * views.size();
    glNamedBufferData(buffers_[4], GLsizeiptr(all * sizeof(glm::vec4)), nullptr, GL_STREAM_READ);
    glNamedBufferData(buffers_[5], GLsizeiptr(all * sizeof(float)), nullptr, GL_STREAM_READ);
    const std::size_t baseNodes = overlay ? std::max<std::size_t>(1, index.nodes.size()) : index.nodes.size();
    const std::size_t countedNodes = baseNodes + (overlay ? overlay->index.nodes.size() : 0);
    std::vector<std::uint32_t> zeros(settings.countRays ? countedNodes : 1, 0u);
    glNamedBufferData(buffers_[6], GLsizeiptr(zeros.size() * 4), zeros.data(), GL_STREAM_READ);

    // Each view's camera: one entry per view, read by the invocations of dispatch layer z.
    std::vector<ViewBlock> blocks;
    for (const auto& view : views) {
        ViewBlock b{};
        const glm::dvec3 f = glm::normalize(view.target - view.eye);
        const glm::dvec3 r = glm::normalize(glm::cross(f, view.up));
        const glm::dvec3 u = glm::cross(r, f);
        const bool pinhole = view.model == core::View::Model::Pinhole;
        const bool screen = view.model == core::View::Model::Screen;
        b.eye = glm::vec4(glm::vec3(view.eye), screen ? 2.0f : pinhole ? 1.0f : 0.0f);
        b.forward = glm::vec4(glm::vec3(f), pinhole ? float(std::tan(glm::radians(view.fovYDegrees) / 2.0))
                                                    : float(view.orthoHeight / 2.0));
        b.right = glm::vec4(glm::vec3(r), float(view.width) / float(view.height));
        b.up = glm::vec4(glm::vec3(u), 0.0f);
        b.screenCentre = glm::vec4(glm::vec3(view.screen.centre), float(view.screen.eta));
        b.screenRight = glm::vec4(glm::vec3(glm::normalize(view.screen.right)), float(view.screen.widthMm));
        b.screenUp = glm::vec4(glm::vec3(glm::normalize(view.screen.up)), float(view.screen.heightMm));
        b.screenViewer = glm::vec4(glm::vec3(view.screen.viewer), 0.0f);
        b.screenProjector = glm::vec4(glm::vec3(view.screen.projector), 0.0f);
        blocks.push_back(b);
    }
    glNamedBufferData(buffers_[10], GLsizeiptr(blocks.size() * sizeof(ViewBlock)), blocks.data(), GL_STREAM_DRAW);

    const auto space = core::OctreeSpace::of(reader.geometry(), reader.brickSize(), reader.levelCount());
    FrameBlock fb{};
    fb.patientToOctree = glm::mat4(space.patientToOctree);
    fb.extent = glm::vec4(glm::vec3(space.extent), float(1.0 / space.rootVoxels));
    fb.tfRange = glm::vec4(float(tf.valueMin()), float(tf.valueMax()), float(settings.earlyTermination),
                           float(settings.stepScale));
    fb.shading = glm::vec4(float(settings.ambient), float(settings.diffuse), float(settings.specular),
                           float(settings.shininess));
    fb.extra = glm::vec4(float(settings.isoValue), settings.shading ? 1.0f : 0.0f, settings.countRays ? 1.0f : 0.0f,
                         float(tf.referenceLength()));
    fb.enhance = glm::vec4(float(settings.boundary), float(settings.viewTransparency),
                           float(space.minSpacing / (tf.valueMax() - tf.valueMin()) / core::kBoundaryGradientFraction),
                           tf.hasGradientOpacity() ? float(tf.gradientMax()) : 0.0f);
    fb.brick = glm::uvec4(reader.brickSize(), reader.border(), reader.brickEdge(), pools_[0].row);
    fb.image = glm::uvec4(std::uint32_t(width), std::uint32_t(height), pools_[0].layer, std::uint32_t(views.size()));
    fb.cropLo = glm::vec4(glm::vec3(settings.crop.min * space.extent), 0.0f);
    fb.cropHi = glm::vec4(glm::vec3(settings.crop.max * space.extent), 0.0f);
    if (overlay) {
        const auto& o = overlay->reader;
        const auto spaceB = core::OctreeSpace::of(o.geometry(), o.brickSize(), o.levelCount());
        fb.patientToOctreeB = glm::mat4(spaceB.patientToOctree);
        fb.extentB = glm::vec4(glm::vec3(spaceB.extent), float(1.0 / spaceB.rootVoxels));
        fb.tfRangeB = glm::vec4(float(overlay->tf.valueMin()), float(overlay->tf.valueMax()),
                                overlay->tf.hasGradientOpacity() ? float(overlay->tf.gradientMax()) : 0.0f, 0.0f);
        fb.brickB = glm::uvec4(o.brickSize(), o.border(), o.brickEdge(), pools_[1].row);
        fb.fusionB = glm::uvec4(pools_[1].layer, std::uint32_t(pools_[0].records.size()),
                                std::uint32_t(std::max<std::size_t>(1, index.nodes.size())), 0u);
    }
    // A quincunx sub-frame (RenderSettings::subFrame): every other pixel of every other row.
    const int stride = settings.subFrame >= 0 ? 2 : 1;
    const glm::ivec2 phase = settings.subFrame >= 0 ? core::FrameReconstructor::phase(settings.subFrame) : glm::ivec2(0);
    fb.pixels = glm::uvec4(std::uint32_t(phase.x), std::uint32_t(phase.y), std::uint32_t(stride), 0u);
    fb.detail = glm::vec4(float(settings.normalUnsharp), float(settings.exaggeratedShading), 0.0f, 0.0f);
    glNamedBufferData(buffers_[7], sizeof fb, &fb, GL_STREAM_DRAW);

    program->use();
    for (GLuint b = 0; b < 7; ++b) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, buffers_[b]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, buffers_[8]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, buffers_[10]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, buffers_[11]);
    if (gradient) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, buffers_[12]);
    if (refract) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, buffers_[13]);
    if (multilevel || detailParent) {
        static_assert(sizeof(core::SpatialIndex::LevelLink) == 64 && core::SpatialIndex::kLevelSpan == 6,
                      "std430 layout of HvxLevelLink (raycast_inputs.glsl, HVX_LEVEL_SPAN)");
        glNamedBufferData(buffers_[14], GLsizeiptr(index.levels.size() * sizeof(core::SpatialIndex::LevelLink)), index.levels.data(),
                          GL_STREAM_DRAW);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, buffers_[14]);
    }
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, buffers_[7]);
    glBindBufferBase(GL_UNIFORM_BUFFER, 1, buffers_[9]);
    // Each sampler type its own units: a split-voxel pool is an integer texture (unit 2).
    glBindTextureUnit(0, split ? 0 : pools_[0].texture);
    glBindTextureUnit(1, overlay ? pools_[1].texture : split ? 0 : pools_[0].texture);
    glBindTextureUnit(2, split ? pools_[0].texture : 0);
    const int across = (width + stride - 1) / stride, down = (height + stride - 1) / stride;
    glDispatchCompute(GLuint((across + 7) / 8), GLuint((down + 7) / 8), GLuint(views.size()));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

    std::vector<core::RenderImage> images(views.size());
    for (std::size_t v = 0; v < views.size(); ++v) {
        auto& img = images[v];
        img.width = width;
        img.height = height;
        img.rgba.resize(pixels);
        img.depth.resize(pixels);
        glGetNamedBufferSubData(buffers_[4], GLintptr(v * pixels * sizeof(glm::vec4)), GLsizeiptr(pixels * sizeof(glm::vec4)),
                                img.rgba.data());
        glGetNamedBufferSubData(buffers_[5], GLintptr(v * pixels * sizeof(float)), GLsizeiptr(pixels * sizeof(float)),
                                img.depth.data());
    }
    if (settings.countRays) {  // rays of every view of the batch, per index node
        images.front().rayCounts.resize(index.nodes.size());
        glGetNamedBufferSubData(buffers_[6], 0, GLsizeiptr(index.nodes.size() * 4), images.front().rayCounts.data());
        if (overlay) {
            images.front().overlayRayCounts.resize(overlay->index.nodes.size());
            glGetNamedBufferSubData(buffers_[6], GLintptr(baseNodes * 4), GLsizeiptr(overlay->index.nodes.size() * 4),
                                    images.front().overlayRayCounts.data());
        }
    }
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) throw core::Error("OpenGL error " + std::to_string(err) + " while ray casting");
    return images;
}

}  // namespace hvx::render
