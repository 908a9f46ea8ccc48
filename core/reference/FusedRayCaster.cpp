#include "core/reference/FusedRayCaster.h"
#include "core/reference/RayCells.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/base/Error.h"
#include "core/base/ThreadPool.h"
#include "core/reference/PixelRays.h"
#include "core/streaming/SpatialIndexTraversal.h"

namespace hvx::core {

FusedRayCaster::FusedRayCaster(const CpuRayCaster& base, const CpuRayCaster& overlay) : a_(base), b_(overlay) {
    if (base.settings_.mode != RenderSettings::Mode::Dvr || overlay.settings_.mode != RenderSettings::Mode::Dvr)
        throw Error("two volumes are fused in 3D in DVR only");
    if (base.settings_.tools.variantBits() || overlay.settings_.tools.variantBits())
        throw Error("the illustrative tools are not drawn over a fused volume");
}

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}  // namespace

/// One volume's walk along the ray: where the current sample is in its index, the leaf's
/// sampler and step, and the previous sample of its segment.
struct FusedRayCaster::Cursor {
    const CpuRayCaster* caster = nullptr;
    glm::vec3 o{}, d{}, inv{};
    float octPerMm = 1.0f, nudge = 0.0f;
    float tLo = kInf, tHi = -kInf;  // the ray inside the volume's box (or crop box)
    float tExit = -kInf;            // where the ray leaves the current leaf (or the empty stretch)
    bool empty = true;
    CpuRayCaster::Leaf leaf;
    glm::vec3 leafLo{};         // the leaf's corner and the size of its 4×4×4 cells (octree units)
    float cell = 1.0f;
    std::uint64_t cells = ~std::uint64_t(0);  // which of them may show (core::BrickCells)
    float dt = kInf;
    float quietUntil = 0.0f;  // after a step: where the stretch that cannot show ends (t when it can show)
    float sPrev = 0.0f, tPrev = 0.0f;
    bool havePrev = false;
};

namespace {
/// The ray's interval inside the box [lo, hi] of octree space (as CpuRayCaster::walk), in world mm.
void clip(const glm::dvec3& od, const glm::dvec3& dd, const glm::dvec3& lo, const glm::dvec3& hi, float& t0, float& t1) {
    double a0 = 0.0, a1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (std::abs(dd[a]) < 1e-15) {
            if (od[a] < lo[a] || od[a] > hi[a]) a1 = -1.0;
            continue;
        }
        double ta = (lo[a] - od[a]) / dd[a], tb = (hi[a] - od[a]) / dd[a];
        if (ta > tb) std::swap(ta, tb);
        a0 = std::max(a0, ta);
        a1 = std::min(a1, tb);
    }
    t0 = float(a0);
    t1 = a1 > a0 ? float(a1) : -kInf;
}
}  // namespace

glm::vec4 FusedRayCaster::cast(const glm::dvec3& ow, const glm::dvec3& dw, float& depth) const {
    depth = kInf;
    Cursor cursors[2];
    for (int v = 0; v < 2; ++v) {
        const CpuRayCaster& c = v == 0 ? a_ : b_;
        Cursor& k = cursors[v];
        k.caster = &c;
        const glm::dvec3 od = glm::dvec3(c.space_.patientToOctree * glm::dvec4(ow, 1.0));
        const glm::dvec3 dd = glm::dmat3(c.space_.patientToOctree) * dw;
        // The base volume is cut by its crop box; the overlay shows whole, inside the base's box.
        const glm::dvec3 lo = v == 0 ? a_.settings_.crop.min * c.space_.extent : glm::dvec3(0.0);
        const glm::dvec3 hi = v == 0 ? a_.settings_.crop.max * c.space_.extent : c.space_.extent;
        clip(od, dd, lo, hi, k.tLo, k.tHi);
        k.o = glm::vec3(od);
        k.d = glm::vec3(dd);
        k.inv = ray_cells::inverse(k.d);
        k.octPerMm = glm::length(k.d);
        k.nudge = float(1e-3 / c.space_.rootVoxels / std::max(1e-12, glm::length(dd)));
    }
    const float t0 = cursors[0].tLo, t1 = cursors[0].tHi;
    if (!(t1 > t0)) return glm::vec4(0.0f);
    // Finds the leaf of a volume holding the ray at t (a nudge on, so that a point on a face
    // belongs to the leaf the ray enters), or the stretch of the ray outside the volume.
    auto locate = [&](Cursor& k, float t) {
        const auto& index = k.caster->index_;
        if (t < k.tLo || t >= k.tHi || index.nodes.empty()) {
            k.empty = true;
            k.tExit = t < k.tLo ? k.tLo : kInf;
            return;
        }
        std::uint32_t n = 0;
        glm::vec3 lo(0.0f), hi(1.0f);
        glsl::hvxDescend(index, n, lo, hi, k.o + (t + k.nudge) * k.d);
        float tExit = 0.0f;
        glsl::hvxExitFace(k.o, k.inv, lo, hi, tExit);
        k.tExit = std::min(tExit, k.tHi);
        const auto& nd = index.nodes[n];
        k.empty = nd.x == SpatialIndex::kNone;
        if (k.empty) return;
        k.leaf = k.caster->leaf(n, lo, false);  // each volume at its leaf's level, as raycast_fusion.glsl
        k.leafLo = lo;
        k.cell = 0.25f / float(1u << (nd.y & 0xFFu));
        k.cells = k.caster->visibleCells(nd.x);
        const float voxel = 1.0f / (float(k.caster->reader_.brickSize()) * float(1u << (nd.y & 0xFFu)));
        k.dt = float(a_.settings_.stepScale) * voxel / k.octPerMm;
    };
    const auto& s = a_.settings_;
    glm::dvec3 color(0.0);
    double alpha = 0.0;
    bool hit = false;
    float t = t0;
    for (auto& k : cursors) locate(k, t);
    for (int guard = 0; guard < 1 << 22 && t <= t1; ++guard) {
        for (auto& k : cursors)
            if (t >= k.tExit) locate(k, t);
        if (cursors[0].empty && cursors[1].empty) {  // nothing in either volume: on to the nearer leaf
            float next = std::min(cursors[0].tExit, cursors[1].tExit);
            if (!(next > t)) next = t + cursors[0].nudge;  // a leaf left at t itself (float rounding)
            if (next > t1) break;
            t = next;
            for (auto& k : cursors) k.havePrev = false;
            continue;
        }
        const float dt = std::min(cursors[0].empty ? kInf : cursors[0].dt, cursors[1].empty ? kInf : cursors[1].dt);
        double a[2] = {0.0, 0.0};
        glm::dvec3 c[2];
        for (int v = 0; v < 2; ++v) {
            Cursor& k = cursors[v];
            k.quietUntil = t;
            if (k.empty) {
                k.havePrev = false;
                k.quietUntil = k.tExit;
                continue;
            }
            const CpuRayCaster& caster = *k.caster;
            const glm::vec3 p = k.o + t * k.d;
            // A cell that cannot show adds nothing, nor does a segment between two of its
            // samples: not sampled; the segment into the next cell that can show starts from a
            // fresh sample before it, as a dense march would have it.
            const glm::ivec3 ci = ray_cells::index(p, k.leafLo, k.cell);
            if (!ray_cells::visible(k.cells, ci)) {
                k.havePrev = false;
                k.quietUntil = ray_cells::exit(ci, k.leafLo, k.cell, k.o, k.inv);
                continue;
            }
            const float sv = caster.sample(k.leaf, p);
            // After empty space, the segment into this brick starts at its border sample.
            if (!k.havePrev && t - dt >= std::max(t0, k.tLo)) {
                k.sPrev = caster.sample(k.leaf, k.o + (t - dt) * k.d);
                k.tPrev = t - dt;
                k.havePrev = true;
            }
            if (k.havePrev) {
                a[v] = 1.0 - std::exp(-caster.segmentExtinction(k.sPrev, sv) * double(t - k.tPrev));
                if (a[v] > 1e-6) {
                    const glm::dvec4 f = caster.segment(k.sPrev, sv);
                    const glm::dvec3 base = glm::dvec3(f) / f.w;
                    c[v] = base;
                    // This volume's own gradient: its opacity curve (raycast_inputs.glsl's
                    // gradientOpacityOf), then headlight Phong.
                    const bool scaled = caster.tf_.hasGradientOpacity();
                    if (s.shading || scaled) {
                        const glm::dvec3 g = caster.normalToWorld_ * glm::dvec3(caster.gradient(k.leaf, p));
                        const double len = glm::length(g);
                        if (scaled) a[v] = caster.scaleByGradient(a[v], len);
                        const double facing = len < 1e-9 ? 0.0 : std::abs(glm::dot(g / len, -dw));
                        if (s.shading)
                            c[v] = len < 1e-9 ? base * (s.ambient + s.diffuse)
                                              : base * (s.ambient + s.diffuse * facing) +
                                                    glm::dvec3(s.specular * std::pow(facing, s.shininess));
                    }
                } else {
                    a[v] = 0.0;
                }
            }
            k.sPrev = sv;
            k.tPrev = t;
            k.havePrev = true;
        }
        const double both = 1.0 - (1.0 - a[0]) * (1.0 - a[1]);
        if (both > 1e-6) {
            const glm::dvec3 mixed = (a[0] * (a[0] > 0 ? c[0] : glm::dvec3(0.0)) + a[1] * (a[1] > 0 ? c[1] : glm::dvec3(0.0))) /
                                     (a[0] + a[1]);
            color += (1.0 - alpha) * both * mixed;
            alpha += (1.0 - alpha) * both;
            if (!hit && alpha > 0.02) {
                hit = true;
                depth = t;
            }
            if (alpha >= s.earlyTermination) break;
        } else if (cursors[0].quietUntil > t && cursors[1].quietUntil > t) {
            // Neither volume can show before the nearer of their quiet stretches ends: land on
            // the last sample before it, as the single-volume march steps over a cell.
            const float k = std::ceil((std::min(cursors[0].quietUntil, cursors[1].quietUntil) - t) / dt);
            if (k >= 3.0f) t += (k - 2.0f) * dt;
        }
        t += dt;
    }
    return glm::vec4(glm::vec3(color), float(alpha));
}

RenderImage FusedRayCaster::render(const View& view) const {
    return castPixelRays(view, [this](const glm::dvec3& o, const glm::dvec3& d, float& depth) { return cast(o, d, depth); });
}

}  // namespace hvx::core
