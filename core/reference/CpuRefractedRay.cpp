// CpuRayCaster's refract stepper (thesis §3.2.2, Figs 3.4–3.5): step for step, and in the same
// float operations, as resources/shaders/raycast_refract.glsl. Each step goes one voxel of the
// current leaf along the ray's current direction; the point reached is tested against the leaf
// and the crop box (a point in another leaf is found from the root); empty leaves and the cells
// of a brick that neither show nor refract are crossed straight (index 1); where a segment's
// pre-integrated refraction index differs from the one the ray travels in, the direction bends by Snell's law (core::glsl::hvxRefractStep) about the
// gradient's normal (the last boundary's where the gradient at the sample is 0).
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/appearance/Refraction.h"
#include "core/reference/CpuRayCaster.h"
#include "core/reference/RayCells.h"
#include "core/streaming/SpatialIndexTraversal.h"

namespace hvx::core {

namespace {
bool insideBox(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
    return glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi));
}
bool insideLeaf(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
    return glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThan(p, hi));
}
}  // namespace

glm::vec4 CpuRayCaster::castRefracted(const glm::dvec3& ow, const glm::dvec3& dw, float& depth,
                                      std::vector<std::uint32_t>* counts) const {
    depth = std::numeric_limits<float>::infinity();
    const glm::mat4 toOctree(space_.patientToOctree);
    const glm::mat3 toOctree3(toOctree), normalToWorld(glm::transpose(toOctree3));
    const glm::vec3 o = glm::vec3(toOctree * glm::vec4(glm::vec3(ow), 1.0f));
    glm::vec3 w = glm::vec3(dw);    // the ray's unit direction (patient mm); bends
    glm::vec3 d = toOctree3 * w;    // the same, octree units per mm
    const glm::vec3 cropLo = glm::vec3(settings_.crop.min * space_.extent), cropHi = glm::vec3(settings_.crop.max * space_.extent);
    // The straight ray's entry into the crop box (raycast_march.glsl's clipToCrop).
    float t0 = 0.0f, t1 = 1e30f;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-15f) {
            if (o[a] < cropLo[a] || o[a] > cropHi[a]) return glm::vec4(0.0f);
            continue;
        }
        const float ta = (cropLo[a] - o[a]) / d[a], tb = (cropHi[a] - o[a]) / d[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    if (!(t1 > t0)) return glm::vec4(0.0f);
    const float nudge = float(1e-3 / space_.rootVoxels);  // a thousandth of a level-0 voxel (octree units)
    float t = t0 + nudge / glm::length(d);
    glm::vec3 p = o + t * d;
    std::uint32_t n = 0;
    glm::vec3 lo(0.0f), hi(1.0f);
    glsl::hvxDescend(index_, n, lo, hi, p);
    const float stepScale = float(settings_.stepScale), stop = float(settings_.earlyTermination);
    glm::dvec3 color(0.0);
    double alpha = 0.0;
    bool hit = false, havePrev = false, inBrick = false;
    bool clear = false;  // the ray has crossed clear space (index 1) since its last segment
    float sPrev = 0.0f, nuPrev = 1.0f, voxel = 1.0f;
    glm::vec3 normal(0.0f);  // the last boundary's gradient: a change of index a step behind bends about it
    Leaf L;
    auto enter = [&](std::uint32_t node) {
        if (counts) ++(*counts)[node];
        L = leaf(node, lo);
        voxel = 1.0f / (float(reader_.brickSize()) * float(1u << (index_.nodes[node].y & 0xFFu)));
        inBrick = true;
    };
    for (int guard = 0; guard < 262144; ++guard) {
        if (!inBrick) {  // p lies in leaf n
            if (index_.nodes[n].x == SpatialIndex::kNone) {  // empty: straight across
                float tExit = 0.0f;
                const int face = glsl::hvxExitFace(p, ray_cells::inverse(d), lo, hi, tExit);
                const float across = std::max(tExit, 0.0f) + nudge / glm::length(d);
                const glm::vec3 q = p + across * d;
                if (!insideBox(q, cropLo, cropHi)) break;
                if (!glsl::hvxNextLeaf(index_, p, d, face, std::max(tExit, 0.0f), nudge / glm::length(d), n, lo, hi)) break;
                p = q;
                t += across;
                havePrev = false;
                clear = true;
                continue;
            }
            enter(n);
        }
        // A cell that neither shows nor refracts bends nothing: land on the last step before
        // its exit, on the ray's own steps (as the shader).
        const float dt = stepScale * voxel / glm::length(d);
        const std::uint32_t slot = index_.nodes[n].x;
        const float cell = 0.25f / float(1u << (index_.nodes[n].y & 0xFFu));
        const glm::ivec3 at = ray_cells::index(p, lo, cell);
        if (!ray_cells::visible(leafCells(L, slot), at)) {
            // p + k·dt: the first step past the cell's exit
            const float k = std::ceil(ray_cells::exit(at, lo, cell, p, ray_cells::inverse(d)) / dt);
            if (k >= 3.0f) {
                p += (k - 1.0f) * dt * d;
                t += (k - 1.0f) * dt;
                if (!insideBox(p, cropLo, cropHi)) break;
                havePrev = false;
                clear = true;
            }
        }
        if (!havePrev) {  // the chain of segments starts here: after clear space in index 1, on
            sPrev = sample(L, p);  // entering the volume in the medium found (a cut face is no boundary)
            nuPrev = clear ? 1.0f : tf_.refractionSegment(sPrev, sPrev);
            havePrev = true;
        }
        const glm::vec3 q = p + dt * d;
        if (!insideBox(q, cropLo, cropHi)) break;
        p = q;
        t += dt;
        if (!insideLeaf(q, lo, hi)) {  // the step ended in another leaf
            n = 0;
            lo = glm::vec3(0.0f);
            hi = glm::vec3(1.0f);
            glsl::hvxDescend(index_, n, lo, hi, q);
            inBrick = false;
            if (index_.nodes[n].x == SpatialIndex::kNone) {
                havePrev = false;
                clear = true;
                continue;
            }
            enter(n);
        }
        const float s = sample(L, p);
        double a = 1.0 - std::exp(-segmentExtinction(sPrev, s) * double(dt));
        const float nu = tf_.refractionSegment(sPrev, s);
        if (a > 1e-6) {
            const glm::dvec4 f = segment(sPrev, s);
            const glm::dvec3 c = shadeSample(L, p, glm::dvec3(f) / f.w, glm::dvec3(w), a);
            color += (1.0 - alpha) * a * c;
            alpha += (1.0 - alpha) * a;
            if (!hit && alpha > 0.02) {
                hit = true;
                depth = t;
            }
            if (alpha >= stop) break;
        }
        if (std::abs(nu - nuPrev) > 1e-5f) {
            const glm::vec3 g = normalToWorld * gradient(L, p);
            if (glm::dot(g, g) > 0.0f) normal = g;
            if (glm::dot(normal, normal) > 0.0f) {  // else the change waits for a boundary
                w = glsl::hvxRefractStep(w, normal, nuPrev, nu);
                d = toOctree3 * w;
                nuPrev = nu;
            }
        }
        sPrev = s;
    }
    return glm::vec4(glm::vec3(color), float(alpha));
}

}  // namespace hvx::core
