#include "core/reference/CpuRayCaster.h"
#include "core/reference/SplitCellMarch.h"
#include "core/reference/RayCells.h"
#include "core/reference/ToolColour.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/streaming/BrickCells.h"
#include "core/streaming/SpatialIndexTraversal.h"
#include "core/base/ThreadPool.h"

namespace hvx::core {

CpuRayCaster::CpuRayCaster(const OctreeReader& reader, const SpatialIndex& index,
                           const std::vector<std::shared_ptr<const std::vector<float>>>& slots,
                           const TransferFunction& tf, RenderSettings settings)
    : reader_(reader), index_(index), slots_(slots), tf_(tf), settings_(settings), labels_(reader.geometry().isLabel),
      space_(OctreeSpace::of(reader.geometry(), reader.brickSize(), reader.levelCount())) {
    normalToWorld_ = glm::transpose(glm::inverse(glm::dmat3(space_.octreeToPatient)));
    strengthPerGradient_ = space_.minSpacing / (tf_.valueMax() - tf_.valueMin()) / kBoundaryGradientFraction;
    settings_.tools.validate();
    packedTools = packTools(settings_.tools, {settings_.ambient, settings_.diffuse, settings_.specular, settings_.shininess});
    // The cells of each brick the rays may skip (as render::GpuRayCaster), for the slots the
    // index uses.
    const bool dvr = settings_.mode == RenderSettings::Mode::Dvr;
    if (reader_.splitVoxels() && settings_.mode != RenderSettings::Mode::Dvr)
        throw Error(reader_.path() + ": a split-voxel octree is drawn in DVR");
    // Refraction (CpuRefractedRay.cpp) as the shader's HVX_REFRACT: DVR, without the tools or split-voxels.
    refracting_ = dvr && tf_.hasRefraction();
    multilevel_ = settings_.multilevel && !labels_ && !settings_.nearest && !reader_.splitVoxels() && index_.blendingLeaves > 0;
    // As the shader's HVX_DETAIL_PARENT: the detail shading draws (tools apply in DVR only and
    // switch it off there) and leaves know their parents.
    detailParents_ = settings_.detailShading() && !(dvr && settings_.tools.any()) && !reader_.splitVoxels() &&
                     !index_.levels.empty();
    if (refracting_ && (settings_.tools.any() || reader_.splitVoxels()))
        throw Error("refraction is drawn without the illustrative tools, a fused volume or split-voxels");
    if (settings_.skipEmptyCells && !reader_.splitVoxels() && (dvr || settings_.mode == RenderSettings::Mode::Iso)) {
        visibleCells_.assign(slots_.size(), ~std::uint64_t(0));
        std::vector<std::uint32_t> used;
        for (const auto& nd : index_.nodes)
            if ((nd.y & SpatialIndex::kLeafBit) && nd.x != SpatialIndex::kNone && nd.x < slots_.size() && slots_[nd.x])
                used.push_back(nd.x);
        ThreadPool::shared().parallelFor(
            used.size(),
            [&](std::size_t a, std::size_t b) {
                for (std::size_t i = a; i < b; ++i) {
                    const auto cells =
                        BrickCells::ofSamples(slots_[used[i]]->data(), reader_.brickSize(), reader_.border());
                    visibleCells_[used[i]] = dvr ? cells.visible(tf_) : cells.straddling(settings_.isoValue);
                }
            },
            16);
    }
}

template <class Visitor>
void CpuRayCaster::walk(const glm::dvec3& ow, const glm::dvec3& dw, Visitor&& visit) const {
    const glm::dvec3 od = glm::dvec3(space_.patientToOctree * glm::dvec4(ow, 1.0));
    const glm::dvec3 dd = glm::dmat3(space_.patientToOctree) * dw;
    // Clip to the volume's box in octree space, or to the crop box in it (t stays in world mm).
    const glm::dvec3 boxLo = settings_.crop.min * space_.extent, boxHi = settings_.crop.max * space_.extent;
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (std::abs(dd[a]) < 1e-15) {
            if (od[a] < boxLo[a] || od[a] > boxHi[a]) return;
            continue;
        }
        double ta = (boxLo[a] - od[a]) / dd[a], tb = (boxHi[a] - od[a]) / dd[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (!(t1 > t0)) return;
    const glm::vec3 o(od), d(dd);
    const glm::vec3 inv = ray_cells::inverse(d);
    // Step past a face by a thousandth of a level-0 voxel, far above float resolution.
    const float nudge = float(1e-3 / space_.rootVoxels / std::max(1e-12, glm::length(dd)));
    std::uint32_t n = 0;
    glm::vec3 lo(0.0f), hi(1.0f);
    glsl::hvxDescend(index_, n, lo, hi, o + (float(t0) + nudge) * d);
    float tIn = float(t0);
    for (int guard = 0; guard < 1 << 20; ++guard) {
        float tExit = 0;
        const int face = glsl::hvxExitFace(o, inv, lo, hi, tExit);
        const float tOut = std::min(tExit, float(t1));
        if (tOut > tIn && !visit(n, lo, tIn, tOut)) return;
        if (tExit >= float(t1)) return;
        if (!glsl::hvxNextLeaf(index_, o, d, face, tExit, nudge, n, lo, hi)) return;
        tIn = std::max(tIn, tExit);
    }
}

std::vector<CpuRayCaster::Visit> CpuRayCaster::traverse(const glm::dvec3& origin, const glm::dvec3& direction) const {
    std::vector<Visit> out;
    walk(origin, direction, [&](std::uint32_t n, const glm::vec3&, float a, float b) {
        out.push_back({n, a, b});
        return true;
    });
    return out;
}

CpuRayCaster::Leaf CpuRayCaster::leaf(std::uint32_t node, const glm::vec3& leafLo, bool levels) const {
    const auto& nd = index_.nodes[node];
    const std::uint32_t depth = nd.y & 0xFFu;
    Leaf L;
    L.data = slots_[nd.x]->data();
    L.scale = float(reader_.brickSize()) * float(1u << depth);
    L.edge = int(reader_.brickEdge());
    // The leaf's grid origin in level voxels (from its box, not from a sample: samples just
    // outside the leaf read its border).
    L.origin = glm::floor(leafLo * float(1u << depth) + 0.5f) * float(reader_.brickSize()) - float(reader_.border());
    if (levels && (multilevel_ || detailParents_) && depth > 0 && node < index_.levels.size()) {
        const auto& lv = index_.levels[node];
        const bool blends = multilevel_ && lv.blends != 0u;
        auto slot = [&](std::uint32_t id) -> const float* {
            return id != SpatialIndex::kNone && id < slots_.size() && slots_[id] ? slots_[id]->data() : nullptr;
        };
        if (slot(lv.ancestors[0]) && (blends || detailParents_)) {
            // the ancestors' box corners: the leaf's, rounded down to their grids (exact in float)
            auto origin = [&](std::uint32_t up) {
                return glm::floor(leafLo * float(1u << (depth - up)) + 0.5f / float(1u << up)) * float(reader_.brickSize()) -
                       float(reader_.border());
            };
            L.ancestor[0] = slot(lv.ancestors[0]);
            L.ancestorOrigin[0] = origin(1);
            if (blends) {
                L.blends = true;
                std::copy(std::begin(lv.coarser), std::end(lv.coarser), std::begin(L.coarser));
                L.highest = *std::max_element(std::begin(lv.coarser), std::end(lv.coarser));
                L.lo = leafLo;
                L.size = 1.0f / float(1u << depth);
                for (std::uint32_t k = 1; k < SpatialIndex::kLevelSpan && k < depth && slot(lv.ancestors[k]); ++k) {
                    L.ancestor[k] = slot(lv.ancestors[k]);
                    L.ancestorOrigin[k] = origin(k + 1);
                }
            }
        }
    }
    return L;
}

float CpuRayCaster::sample(const Leaf& L, const glm::vec3& p) const {
    return labels_ || settings_.nearest ? nearest(L, p) : linear(L, p);
}

float CpuRayCaster::nearest(const Leaf& L, const glm::vec3& p) const {
    const int e = L.edge;
    const glm::ivec3 i = glm::clamp(glm::ivec3(glm::floor(p * L.scale - L.origin)), glm::ivec3(0), glm::ivec3(e - 1));
    return L.data[(std::size_t(i.z) * std::size_t(e) + std::size_t(i.y)) * std::size_t(e) + std::size_t(i.x)];
}

float CpuRayCaster::levelOffset(const Leaf& L, const glm::vec3& p) {
    const glm::vec3 u = glm::clamp((p - L.lo) / L.size, glm::vec3(0.0f), glm::vec3(1.0f));
    float f = 0.0f;
    for (std::uint32_t c = 0; c < 8; ++c)
        f += L.coarser[c] * (((c & 1u) ? u.x : 1.0f - u.x) * ((c & 2u) ? u.y : 1.0f - u.y) * ((c & 4u) ? u.z : 1.0f - u.z));
    return std::min(f, L.highest);
}

float CpuRayCaster::linear(const Leaf& L, const glm::vec3& p) const {
    const float own = trilinear(L.data, L.edge, L.scale, L.origin, p);
    if (!L.blends) return own;
    // Quadrilinear: trilinear at the two levels around the field's, blended.
    const float f = levelOffset(L, p);
    auto ancestor = [&](std::uint32_t up) {  // trilinear in the ancestor `up` levels up (linkParents keeps f within those resident)
        return trilinear(L.ancestor[up - 1], L.edge, L.scale / float(1u << up), L.ancestorOrigin[up - 1], p);
    };
    if (f <= 1.0f) return own * (1.0f - f) + ancestor(1) * f;
    const float k = std::ceil(f) - 1.0f;  // between the ancestors k and k + 1 levels up
    return ancestor(std::uint32_t(k)) * (k + 1.0f - f) + ancestor(std::uint32_t(k) + 1) * (f - k);
}

float CpuRayCaster::trilinear(const float* data, int e, float scale, const glm::vec3& origin, const glm::vec3& p) {
    glm::vec3 u = p * scale - origin - 0.5f;
    u = glm::clamp(u, glm::vec3(0.0f), glm::vec3(float(e - 1)));
    const glm::ivec3 i0 = glm::min(glm::ivec3(u), glm::ivec3(e - 2 > 0 ? e - 2 : 0));
    const glm::vec3 f = u - glm::vec3(i0);
    auto at = [&](int x, int y, int z) {
        return data[(std::size_t(z) * std::size_t(e) + std::size_t(y)) * std::size_t(e) + std::size_t(x)];
    };
    const int x1 = std::min(i0.x + 1, e - 1), y1 = std::min(i0.y + 1, e - 1), z1 = std::min(i0.z + 1, e - 1);
    const float c00 = at(i0.x, i0.y, i0.z) * (1 - f.x) + at(x1, i0.y, i0.z) * f.x;
    const float c10 = at(i0.x, y1, i0.z) * (1 - f.x) + at(x1, y1, i0.z) * f.x;
    const float c01 = at(i0.x, i0.y, z1) * (1 - f.x) + at(x1, i0.y, z1) * f.x;
    const float c11 = at(i0.x, y1, z1) * (1 - f.x) + at(x1, y1, z1) * f.x;
    return (c00 * (1 - f.y) + c10 * f.y) * (1 - f.z) + (c01 * (1 - f.y) + c11 * f.y) * f.z;
}

namespace {
/// Central differences of `f` at p, `h` apart, in the float operations of brick_sampling.glsl's
/// centralDifference.
template <class F>
glm::vec3 centralDifference(const F& f, const glm::vec3& p, float h) {
    return glm::vec3(f(p + glm::vec3(h, 0, 0)) - f(p - glm::vec3(h, 0, 0)), f(p + glm::vec3(0, h, 0)) - f(p - glm::vec3(0, h, 0)),
                     f(p + glm::vec3(0, 0, h)) - f(p - glm::vec3(0, 0, h))) /
           (2.0f * h);
}
}  // namespace

glm::vec3 CpuRayCaster::gradient(const Leaf& L, const glm::vec3& p, float spread) const {
    return centralDifference([&](const glm::vec3& q) { return linear(L, q); }, p, spread / L.scale);
}

glm::vec3 CpuRayCaster::coarserGradient(const Leaf& L, const glm::vec3& p) const {
    if (!L.ancestor[0]) return gradient(L, p, 2.0f);
    // one voxel of the parent's level apart
    const float parentScale = L.scale * 0.5f;
    return centralDifference([&](const glm::vec3& q) { return trilinear(L.ancestor[0], L.edge, parentScale, L.ancestorOrigin[0], q); },
                             p, 1.0f / parentScale);
}

double CpuRayCaster::scaleByGradient(double a, double len) const {
    const double g = tf_.gradientScale(len), keep = 1.0 - a;
    return g <= 0.0 ? 0.0 : keep <= 0.0 ? 1.0 : 1.0 - std::pow(keep, g);
}

glm::dvec3 CpuRayCaster::shadeSample(const Leaf& L, const glm::vec3& p, const glm::dvec3& base, const glm::dvec3& dw,
                                     double& a) const {
    const auto mode = settings_.mode;
    const bool enhance = settings_.boundary > 0.0 || settings_.viewTransparency > 0.0;
    // Gradient opacity (DVR): a' = 1 - (1 - a)^g(|∇f|), as raycast_inputs.glsl's gradientOpacity.
    const bool gradientOpacity = mode == RenderSettings::Mode::Dvr && tf_.hasGradientOpacity();
    // Tools apply in DVR only; the shader's HVX_DETAIL is off exactly when they do.
    const bool detail = settings_.detailShading() && !(mode == RenderSettings::Mode::Dvr && settings_.tools.any());
    if (!settings_.shading && !enhance && !gradientOpacity) return base;
    glm::dvec3 g = normalToWorld_ * glm::dvec3(gradient(L, p));
    const double len = glm::length(g);
    if (gradientOpacity) a = scaleByGradient(a, len);
    const double facing = len < 1e-9 ? 0.0 : std::abs(glm::dot(g / len, -dw));  // headlight: L = V
    if (enhance) {
        const double strength = std::min(1.0, len * strengthPerGradient_);
        a *= (1.0 - settings_.boundary + settings_.boundary * strength) * (1.0 - settings_.viewTransparency * strength * facing);
    }
    if (!settings_.shading) return base;
    if (len < 1e-9) return base * (settings_.ambient + settings_.diffuse);
    if (detail) {  // as raycast_march.glsl's shadeSample, in float like the shader
        const glm::vec3 gs = glm::vec3(normalToWorld_ * glm::dvec3(coarserGradient(L, p)));
        const glm::vec2 f = glsl::hvxDetailShading(glm::vec3(g), gs, glm::vec3(-dw), float(settings_.normalUnsharp),
                                                   float(settings_.exaggeratedShading),
                                                   std::min(1.0f, float(len) * float(strengthPerGradient_)));
        return base * (settings_.ambient + settings_.diffuse * double(f.x)) +
               glm::dvec3(settings_.specular * std::pow(double(f.y), settings_.shininess));
    }
    return base * (settings_.ambient + settings_.diffuse * facing) +
           glm::dvec3(settings_.specular * std::pow(facing, settings_.shininess));
}

glm::vec4 CpuRayCaster::castSplit(const glm::dvec3& ow, const glm::dvec3& dw, float& depth,
                                  std::vector<std::uint32_t>* counts) const {
    // Each leaf's cells by the DDA of Fig. 4.5 (SplitCellMarch), in the leaf's own cell
    // coordinates: octree units scaled by the leaf's cells per unit, less its first cell.
    const glm::dvec3 o(space_.patientToOctree * glm::dvec4(ow, 1.0));
    const glm::dvec3 d(glm::dmat3(space_.patientToOctree) * dw);
    SplitCompositor out{tf_, settings_, labels_, normalToWorld_, -glm::normalize(dw)};
    out.toolBits = settings_.tools.variantBits();
    out.tools = &packedTools;
    out.origin = ow;
    if (out.toolBits & HVX_FOCAL_BIT) out.hTheta = glsl::hvxFocalAngle(packedTools, glm::vec3(ow), glm::vec3(glm::normalize(dw)));
    SplitMarchState state;
    const int B = int(reader_.brickSize());
    walk(ow, dw, [&](std::uint32_t n, const glm::vec3& lo, float tIn, float tOut) {
        const auto& nd = index_.nodes[n];
        if (nd.x == SpatialIndex::kNone) {  // nothing the transfer function shows
            state.previous = std::numeric_limits<float>::quiet_NaN();
            return true;
        }
        if (counts) ++(*counts)[n];
        const Leaf L = leaf(n, lo);
        const glm::dvec3 oc = o * double(L.scale) - glm::dvec3(L.origin), dc = d * double(L.scale);
        out.piece = double(float(settings_.stepScale) / glm::length(glm::vec3(dc)));  // a cell's length along the ray (mm), as the GPU
        return marchSplitCells(oc, dc, tIn, tOut, glm::ivec3(B),
                               [&](const glm::ivec3& c) {
                                   const float* q = L.data + 6 * ((std::size_t(c.z) * std::size_t(B) + std::size_t(c.y)) * std::size_t(B) + std::size_t(c.x));
                                   return SplitVoxel{q[0], q[1], glm::vec3(q[2], q[3], q[4]), q[5]};
                               },
                               out, state);
    });
    depth = out.depth;
    return glm::vec4(out.accum);
}

glm::vec4 CpuRayCaster::cast(const glm::dvec3& ow, const glm::dvec3& dw, float& depth,
                             std::vector<std::uint32_t>* counts) const {
    if (reader_.splitVoxels()) return castSplit(ow, dw, depth, counts);
    if (refracting_) return castRefracted(ow, dw, depth, counts);
    depth = std::numeric_limits<float>::infinity();
    const glm::vec3 o(space_.patientToOctree * glm::dvec4(ow, 1.0));
    const glm::vec3 d(glm::dmat3(space_.patientToOctree) * dw);
    const float octPerMm = glm::length(d);
    const bool skipping = !visibleCells_.empty();
    const glm::vec3 inv = ray_cells::inverse(d);
    glm::dvec3 color(0.0);
    double alpha = 0.0, extreme = settings_.mode == RenderSettings::Mode::MinIp ? 1e300 : -1e300, sum = 0.0;
    double travelled = 0.0;
    bool hit = false, havePrev = false;
    float tPrev = 0.0f, sPrev = 0.0f;
    const auto mode = settings_.mode;
    Leaf L;  // the leaf being sampled
    const double strengthPerGradient = strengthPerGradient_;
    const bool gradientOpacity = mode == RenderSettings::Mode::Dvr && tf_.hasGradientOpacity();
    auto shade = [&](const glm::vec3& p, const glm::dvec3& base, double& a) { return shadeSample(L, p, base, dw, a); };
    // Tools: per-ray state (focal probe cone, entry) and the MImDA accumulator.
    const int toolBits = settings_.mode == RenderSettings::Mode::Dvr ? settings_.tools.variantBits() : 0;
    const float strengthPerGradientF = float(strengthPerGradient);
    const float gamma = packedTools.bandAxis.w;
    const float hTheta = (toolBits & HVX_FOCAL_BIT) ? glsl::hvxFocalAngle(packedTools, glm::vec3(ow), glm::vec3(dw)) : 1.0f;
    // The focal probe samples its context every kContext·dt, its focus every dt (hvxStepAfter).
    const bool contextSteps = (toolBits & HVX_FOCAL_BIT) != 0;
    const glm::vec2 chord = contextSteps ? glsl::hvxFocusChord(packedTools, toolBits, glm::vec3(ow), glm::vec3(dw))
                                         : glm::vec2(-1e30f, 1e30f);
    const float kContext = packedTools.focalRot0.w;
    bool enteredProbe = false;
    glm::vec4 accum(0.0f);
    float importanceMax = 0.0f;
    float tStart = -1.0f;
    walk(ow, dw, [&](std::uint32_t n, const glm::vec3& lo, float tIn, float tOut) {
        if (tStart < 0.0f) tStart = tIn;
        const auto& nd = index_.nodes[n];
        if (nd.x == SpatialIndex::kNone) {  // empty leaf: nothing to accumulate
            havePrev = false;
            return true;
        }
        if (counts) ++(*counts)[n];
        L = leaf(n, lo);
        const std::uint64_t cellBits = leafCells(L, nd.x);
        const float cell = 0.25f / float(1u << (nd.y & 0xFFu));
        float cellEnd = -1.0f;  // where the ray leaves the cell last looked at (t >= 0)
        const std::uint32_t depthLevel = nd.y & 0xFFu;
        const float voxel = 1.0f / (float(reader_.brickSize()) * float(1u << depthLevel));
        const float dt = float(settings_.stepScale) * voxel / octPerMm;  // world mm
        float t = tPrev + dt;
        if (!havePrev) {
            // After empty space, resume on the ray's own sampling grid and take the segment
            // leading into this brick from its border samples, as a dense marcher would.
            t = tStart + std::ceil((tIn - tStart) / dt) * dt;
            tPrev = t - dt;
            if (tPrev >= tStart) {  // not before the ray entered the volume
                sPrev = sample(L, o + tPrev * d);
                havePrev = mode == RenderSettings::Mode::Dvr || mode == RenderSettings::Mode::Iso;
            }
        }
        for (; t <= tOut; t += contextSteps ? glsl::hvxStepAfter(t, dt, chord, kContext) : dt) {
            const glm::vec3 p = o + t * d;
            const float s = sample(L, p);
            if (mode == RenderSettings::Mode::Dvr) {
                if (havePrev) {
                    // Opacity first: most samples stop there, transparent.
                    const double seg = t - tPrev;
                    double a = 1.0 - std::exp(-segmentExtinction(sPrev, s) * seg);
                    const glm::dvec4 f = a > 1e-6 ? segment(sPrev, s) : glm::dvec4(0.0);
                    if (a > 1e-6 && toolBits) {
                        // Enhancers (core/appearance/Enhancers.glsl), then shading and MImDA
                        // compositing, in the shader's order and precision.
                        const glm::vec3 gOct = gradient(L, p);
                        const glm::vec3 g = glm::vec3(normalToWorld_ * glm::dvec3(gOct));
                        glsl::HvxSample x;
                        x.p = glm::vec3(ow + double(t) * dw);
                        x.v = glm::vec3(dw);
                        x.g = g;
                        x.gn = std::min(1.0f, glm::length(g) * strengthPerGradientF);
                        x.s = s;
                        x.c = glm::vec3(glm::dvec3(f) / f.w);
                        x.a = float(gradientOpacity ? scaleByGradient(a, double(glm::length(g))) : a);
                        x.lit = 1.0f;
                        x.importance = 1.0f - std::exp(-float(f.w) * float(tf_.referenceLength()));
                        const float focalNorm = (toolBits & HVX_FOCAL_BIT) ? glsl::hvxFocalNorm(packedTools, x.p) : 2.0f;
                        const glm::vec3 gSmooth =
                            focalNorm <= 1.0f ? glm::vec3(normalToWorld_ * glm::dvec3(gradient(L, p, 2.0f))) : g;
                        bool enteredNow = enteredProbe;
                        const float kSegment = contextSteps ? glsl::hvxContextSegment(t, tPrev, dt, chord) : 1.0f;
                        x.a = glsl::hvxOpacityPerSample(x.a, kSegment);
                        glsl::hvxEnhance(x, packedTools, toolBits, focalNorm, gSmooth, hTheta, enteredNow);
                        x.a = glsl::hvxOpacityOfSegment(x.a, kSegment);
                        if (enteredNow && !enteredProbe) {  // clip what lies in front of the focal probe
                            accum = glm::vec4(0.0f);
                            importanceMax = 0.0f;
                            enteredProbe = true;
                        }
                        glsl::hvxMimda(accum, importanceMax, toolColour(x, settings_) * x.a, x.a, x.importance, gamma);
                        if (!hit && accum.w > 0.02f) {
                            hit = true;
                            depth = t;
                        }
                        if (glsl::hvxMimdaFutureDelta(accum.w, importanceMax, gamma) < 1.0f - float(settings_.earlyTermination))
                            return false;
                    } else if (a > 1e-6) {
                        const glm::dvec3 c = shade(p, glm::dvec3(f) / f.w, a);
                        color += (1.0 - alpha) * a * c;
                        alpha += (1.0 - alpha) * a;
                        if (!hit && alpha > 0.02) {
                            hit = true;
                            depth = t;
                        }
                        if (alpha >= settings_.earlyTermination) return false;
                    }
                }
            } else if (mode == RenderSettings::Mode::Iso) {
                const double iso = settings_.isoValue;
                if (havePrev && (sPrev < iso) != (s < iso)) {
                    float a = tPrev, b = t, sa = sPrev;
                    for (int k = 0; k < 8; ++k) {  // bisection to the crossing
                        const float m = 0.5f * (a + b);
                        const float sm = sample(L, o + m * d);
                        if ((sa < iso) != (sm < iso))
                            b = m;
                        else {
                            a = m;
                            sa = sm;
                        }
                    }
                    const float th = 0.5f * (a + b);
                    const glm::dvec4 f = tf_.sample(iso);
                    glm::dvec3 base = f.w > 0 ? glm::dvec3(f) / f.w : glm::dvec3(0.9);
                    if (glm::length(base) < 0.1) base = glm::dvec3(0.9);
                    double opaque = 1.0;
                    color = shade(o + th * d, base, opaque);
                    alpha = 1.0;
                    depth = th;
                    return false;
                }
            } else {
                extreme = mode == RenderSettings::Mode::MinIp ? std::min(extreme, double(s)) : std::max(extreme, double(s));
                if (havePrev) {
                    sum += 0.5 * (s + sPrev) * (t - tPrev);
                    travelled += t - tPrev;
                }
                if (!hit) {
                    hit = true;
                    depth = t;
                }
            }
            tPrev = t;
            sPrev = s;
            havePrev = true;
            // In a cell that cannot show, every sample and every segment between two of them
            // adds nothing: land on the last sample before the cell's exit (it starts the next
            // segment) and go on from there, as the shader does. The shader tests every sample
            // (a branch would not spare a SIMD lane); here a cell is looked at once, when the
            // ray enters it.
            if (skipping && t >= cellEnd) {
                const glm::ivec3 c = ray_cells::index(p, lo, cell);
                cellEnd = ray_cells::exit(c, lo, cell, o, inv);
                if (!ray_cells::visible(cellBits, c)) {
                    const float k = std::ceil((cellEnd - t) / dt);  // t + k·dt: the first sample past the exit
                    if (k >= 3.0f) {
                        t += (k - 2.0f) * dt;  // the loop's step makes it t + (k - 1)·dt
                        havePrev = false;
                    }
                }
            }
        }
        return true;
    });
    if (mode == RenderSettings::Mode::Mip || mode == RenderSettings::Mode::MinIp || mode == RenderSettings::Mode::Average) {
        if (!hit) return glm::vec4(0.0f);
        const double v = mode == RenderSettings::Mode::Average ? (travelled > 0 ? sum / travelled : extreme) : extreme;
        const float g = glsl::hvxProjectionLight(float((v - tf_.valueMin()) / (tf_.valueMax() - tf_.valueMin())));
        return glm::vec4(g, g, g, 1.0f);
    }
    if (toolBits) return accum;
    return glm::vec4(glm::vec3(color), float(alpha));
}

RenderImage CpuRayCaster::render(const View& view) const {
    RenderImage img;
    img.width = view.width;
    img.height = view.height;
    img.rgba.assign(std::size_t(view.width) * view.height, glm::vec4(0.0f));
    img.depth.assign(img.rgba.size(), std::numeric_limits<float>::infinity());
    if (index_.nodes.empty()) return img;  // no cut yet (nothing converged): nothing to draw
    std::vector<std::vector<std::uint32_t>> counts;
    const bool count = settings_.countRays;
    ThreadPool::shared().parallelFor(std::size_t(view.height), [&](std::size_t y0, std::size_t y1) {
        std::vector<std::uint32_t> local(count ? index_.nodes.size() : 0, 0);
        for (std::size_t y = y0; y < y1; ++y)
            for (int x = 0; x < view.width; ++x) {
                glm::dvec3 o, d;
                view.ray(x, double(y), o, d);
                const std::size_t i = y * std::size_t(view.width) + std::size_t(x);
                img.rgba[i] = cast(o, d, img.depth[i], count ? &local : nullptr);
            }
        if (count) {
            static std::mutex m;
            std::lock_guard lock(m);
            counts.push_back(std::move(local));
        }
    }, 8);
    if (count) {
        img.rayCounts.assign(index_.nodes.size(), 0);
        for (const auto& c : counts)
            for (std::size_t i = 0; i < c.size(); ++i) img.rayCounts[i] += c[i];
    }
    return img;
}

}  // namespace hvx::core
