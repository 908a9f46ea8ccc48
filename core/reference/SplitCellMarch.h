#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/appearance/Enhancers.h"
#include "core/appearance/TransferFunction.h"
#include "core/octree/SplitVoxel.h"
#include "core/reference/RenderSettings.h"
#include "core/reference/ToolColour.h"

namespace hvx::core {

/// Front-to-back compositing of split-voxel material segments (thesis §4.5.2): a segment of
/// value v and length δt adds the colour of its table entry (labels) or table value
/// (intensities) at opacity 1 − exp(−tau·δt), shaded (RenderSettings' Phong terms, headlight)
/// by a normal when the segment lies at a boundary, else ambient + diffuse as Holovox shades
/// homogeneous regions. With the illustrative tools, a segment is cut into pieces of at most
/// `piece` mm, each a sample of core/appearance/Enhancers.glsl (gradient: the boundary's unit
/// normal at full strength, none inside a material) composited by MImDA, as the voxel march
/// composites its samples. Shared by the split-voxel reference caster and the CPU ray caster's
/// split-voxel leaves.
struct SplitCompositor {
    const TransferFunction& tf;
    const RenderSettings& settings;
    bool labels;
    glm::dmat3 cellNormalToWorld;  ///< normals in cell coordinates to patient space
    glm::dvec3 view;               ///< −ray direction, unit (headlight)
    glm::dvec4 accum{0.0};
    float depth = std::numeric_limits<float>::infinity();
    // The tools (toolBits ≠ 0): the packed set, the ray (world, t in mm), its focal cone and
    // MImDA state, and the longest piece (mm; set per leaf).
    const glsl::HvxTools* tools = nullptr;
    int toolBits = 0;
    glm::dvec3 origin{0.0};
    float hTheta = 1.0f;
    bool entered = false;
    float importanceMax = 0.0f;
    double piece = 1.0;

    /// Adds `value` over [ta, tb] (world mm); `normalCell` in cell coordinates or null. False
    /// once the ray is opaque (RenderSettings::earlyTermination).
    bool add(float value, double ta, double tb, const glm::dvec3* normalCell) {
        if (tb <= ta) return true;
        if (toolBits) return addWithTools(value, ta, tb, normalCell);
        const glm::dvec4 f = labels ? tf.entry(value) : tf.sample(value);
        if (f.w <= 0.0) return true;
        const double alpha = 1.0 - std::exp(-f.w * (tb - ta));
        glm::dvec3 colour = glm::dvec3(f) / f.w;
        if (settings.shading) {
            if (!normalCell) {
                colour *= settings.ambient + settings.diffuse;
            } else {
                const double facing = std::abs(glm::dot(glm::normalize(cellNormalToWorld * *normalCell), view));
                colour = colour * (settings.ambient + settings.diffuse * facing) +
                         glm::dvec3(settings.specular * std::pow(facing, settings.shininess));
            }
        }
        if (accum.w == 0.0) depth = float(ta);
        const double w = (1.0 - accum.w) * alpha;
        accum += glm::dvec4(colour * w, w);
        return accum.w < settings.earlyTermination;
    }

    /// add() with the tools, in the float operations of raycast_split.glsl's splitAdd.
    bool addWithTools(float value, double ta, double tb, const glm::dvec3* normalCell) {
        const glm::dvec4 f = labels ? tf.entry(value) : tf.sample(value);
        if (f.w <= 0.0) return true;
        const glm::vec3 g = normalCell ? glm::vec3(glm::normalize(cellNormalToWorld * *normalCell)) : glm::vec3(0.0f);
        const int pieces = std::max(1, int(std::ceil(float(tb - ta) / float(piece))));
        const float len = float(tb - ta) / float(pieces);
        const float a = 1.0f - std::exp(-float(f.w) * len);
        const glm::vec3 dir = -glm::vec3(view);
        for (int i = 0; i < pieces; ++i) {
            const float t = float(ta) + (float(i) + 0.5f) * len;
            glsl::HvxSample x;
            x.p = glm::vec3(origin) + t * dir;
            x.v = dir;
            x.g = g;
            x.gn = normalCell ? 1.0f : 0.0f;
            x.s = value;
            x.c = glm::vec3(f) / float(f.w);
            x.a = a;
            x.lit = 1.0f;
            x.importance = 1.0f - std::exp(-float(f.w) * float(tf.referenceLength()));
            const float focalNorm = (toolBits & HVX_FOCAL_BIT) ? glsl::hvxFocalNorm(*tools, x.p) : 2.0f;
            bool enteredNow = entered;
            glsl::hvxEnhance(x, *tools, toolBits, focalNorm, g, hTheta, enteredNow);
            glm::vec4 acc(accum);
            if (enteredNow && !entered) {  // clip what lies in front of the focal probe
                acc = glm::vec4(0.0f);
                importanceMax = 0.0f;
                entered = true;
            }
            glsl::hvxMimda(acc, importanceMax, toolColour(x, settings) * x.a, x.a, x.importance, tools->bandAxis.w);
            accum = glm::dvec4(acc);
            if (std::isinf(depth) && acc.w > 0.02f) depth = t;
            if (glsl::hvxMimdaFutureDelta(acc.w, importanceMax, tools->bandAxis.w) < 1.0f - float(settings.earlyTermination))
                return false;
        }
        return true;
    }
};

/// Where a march left off, carried from one box of cells (a leaf) to the next along a ray: the
/// last material it added (NaN: none, or a stretch the transfer function hides).
struct SplitMarchState {
    float previous = std::numeric_limits<float>::quiet_NaN();
};

/// The 3D DDA of Fig. 4.5 over the cells [0, dims) of a box, for the ray o + t·d in the box's
/// cell coordinates (t in world mm) from t0 to t1 (inside the box): each uniform cell adds its
/// value over its length (shaded by the face it was entered through when the material changed
/// there), each split cell its two materials on either side of the plane, in the order the ray
/// meets them, shaded by the plane's normal. `cellAt(ivec3)` returns a SplitVoxel. False once
/// the compositor is opaque.
template <class CellAt>
bool marchSplitCells(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1, const glm::ivec3& dims,
                     CellAt&& cellAt, SplitCompositor& out, SplitMarchState& state) {
    if (t0 >= t1) return true;
    const glm::dvec3 entry = o + d * t0;
    glm::ivec3 cell, step;
    glm::dvec3 tNext, tDelta;
    for (int a = 0; a < 3; ++a) {
        cell[a] = std::clamp(int(std::floor(entry[a])), 0, dims[a] - 1);
        step[a] = d[a] > 0 ? 1 : -1;
        const bool flat = std::abs(d[a]) < 1e-300;
        tDelta[a] = flat ? std::numeric_limits<double>::infinity() : 1.0 / std::abs(d[a]);
        const double face = d[a] > 0 ? cell[a] + 1.0 : double(cell[a]);
        tNext[a] = flat ? std::numeric_limits<double>::infinity() : (face - o[a]) / d[a];
    }
    double tIn = t0;
    int crossed = -1;
    while (tIn < t1) {
        const int a = tNext.x < tNext.y ? (tNext.x < tNext.z ? 0 : 2) : (tNext.y < tNext.z ? 1 : 2);
        const double tOut = std::min(tNext[a], t1);
        const SplitVoxel v = cellAt(cell);
        bool go = true;
        if (v.isUniform()) {
            glm::dvec3 face(0.0);
            const bool changed = !std::isnan(state.previous) && state.previous != v.front;
            if (crossed >= 0 && changed) face[crossed] = 1.0;
            go = out.add(v.front, tIn, tOut, crossed >= 0 && changed ? &face : nullptr);
            state.previous = v.front;
        } else {
            const glm::dvec3 n(v.normal);
            const double dn = glm::dot(n, d);
            const double at = glm::dot(n, o - (glm::dvec3(cell) + 0.5));  // the plane: n·(x − centre) = offset
            if (std::abs(dn) < 1e-300) {  // along the plane: the side the ray runs on
                const float side = at >= v.offset ? v.front : v.back;
                go = out.add(side, tIn, tOut, &n);
                state.previous = side;
            } else {
                // The material met first is the front one when the ray runs against the normal.
                const bool frontFirst = dn <= 0.0;
                const float first = frontFirst ? v.front : v.back, second = frontFirst ? v.back : v.front;
                const double tPlane = (double(v.offset) - at) / dn;
                if (tPlane <= tIn) {
                    go = out.add(second, tIn, tOut, &n);
                    state.previous = second;
                } else if (tPlane >= tOut) {
                    go = out.add(first, tIn, tOut, &n);
                    state.previous = first;
                } else {
                    go = out.add(first, tIn, tPlane, &n) && out.add(second, tPlane, tOut, &n);
                    state.previous = second;
                }
            }
        }
        if (!go) return false;
        if (tOut >= t1) break;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= dims[a]) break;
        tNext[a] += tDelta[a];
        crossed = a;
        tIn = tOut;
    }
    return true;
}

}  // namespace hvx::core
