#include "core/reference/SplitVoxelRayCaster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "core/base/ThreadPool.h"

namespace hvx::core {

SplitVoxelRayCaster::SplitVoxelRayCaster(const SplitVoxelGrid& grid, const VolumeGeometry& geometry,
                                         const TransferFunction& tf, RenderSettings settings)
    : grid_(grid), tf_(tf), settings_(settings), labels_(geometry.isLabel) {
    // cell = (index + ½) / c: cell coordinates of a continuous source index.
    const double c = double(grid.cellVoxels());
    glm::dmat4 indexToCell(1.0 / c);
    indexToCell[3] = glm::dvec4(0.5 / c, 0.5 / c, 0.5 / c, 1.0);
    worldToCell_ = indexToCell * glm::inverse(geometry.indexToPatient());
    cellNormalToWorld_ = glm::transpose(glm::dmat3(worldToCell_));
    extent_ = glm::dvec3(geometry.dims[0], geometry.dims[1], geometry.dims[2]) / c;
}

glm::vec4 SplitVoxelRayCaster::cast(const glm::dvec3& ow, const glm::dvec3& dw, float& depth) const {
    glm::dvec4 accum(0.0);
    const glm::dvec3 o(worldToCell_ * glm::dvec4(ow, 1.0));
    const glm::dvec3 d = glm::dmat3(worldToCell_) * dw;  // t stays world mm along the ray
    // Where the ray crosses the volume's box.
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-300) {
            if (o[a] < 0.0 || o[a] >= extent_[a]) return glm::vec4(0.0f);
            continue;
        }
        double ta = (0.0 - o[a]) / d[a], tb = (extent_[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (t0 >= t1) return glm::vec4(0.0f);
    // DDA set-up (Amanatides & Woo): the cell at entry, the t of the next face on each axis.
    const auto& dims = grid_.dims();
    const glm::dvec3 entry = o + d * t0;
    glm::ivec3 cell, step;
    glm::dvec3 tNext, tDelta;
    for (int a = 0; a < 3; ++a) {
        cell[a] = std::clamp(int(std::floor(entry[a])), 0, int(dims[std::size_t(a)]) - 1);
        step[a] = d[a] > 0 ? 1 : -1;
        tDelta[a] = std::abs(d[a]) < 1e-300 ? std::numeric_limits<double>::infinity() : 1.0 / std::abs(d[a]);
        const double face = d[a] > 0 ? cell[a] + 1.0 : double(cell[a]);
        tNext[a] = std::abs(d[a]) < 1e-300 ? std::numeric_limits<double>::infinity() : (face - o[a]) / d[a];
    }
    const glm::dvec3 view = -glm::normalize(dw);  // headlight
    const auto shaded = [&](const glm::dvec3& base, const glm::dvec3* normalCell) {
        if (!settings_.shading) return base;
        if (!normalCell) return base * (settings_.ambient + settings_.diffuse);
        const glm::dvec3 n = glm::normalize(cellNormalToWorld_ * *normalCell);
        const double facing = std::abs(glm::dot(n, view));
        return base * (settings_.ambient + settings_.diffuse * facing) +
               glm::dvec3(settings_.specular * std::pow(facing, settings_.shininess));
    };
    // Adds a material `value` over [ta, tb]; false once the ray is opaque.
    const auto add = [&](float value, double ta, double tb, const glm::dvec3* normal) {
        if (tb <= ta) return true;
        const glm::dvec4 f = labels_ ? tf_.entry(value) : tf_.sample(value);
        if (f.w <= 0.0) return true;
        const double alpha = 1.0 - std::exp(-f.w * (tb - ta));
        const glm::dvec3 colour = shaded(glm::dvec3(f) / f.w, normal);
        if (accum.w == 0.0) depth = float(ta);
        const double w = (1.0 - accum.w) * alpha;
        accum += glm::dvec4(colour * w, w);
        return accum.w < settings_.earlyTermination;
    };
    double tIn = t0;
    float previous = std::numeric_limits<float>::quiet_NaN();
    int crossed = -1;  // the axis of the face the ray entered this cell through (-1: the box)
    while (tIn < t1) {
        int a = tNext.x < tNext.y ? (tNext.x < tNext.z ? 0 : 2) : (tNext.y < tNext.z ? 1 : 2);
        const double tOut = std::min(tNext[a], t1);
        const SplitVoxel& v = grid_.at(std::uint32_t(cell.x), std::uint32_t(cell.y), std::uint32_t(cell.z));
        bool go = true;
        if (v.isUniform()) {
            glm::dvec3 face(0.0);
            if (crossed >= 0 && previous == previous && previous != v.front) face[crossed] = 1.0;
            go = add(v.front, tIn, tOut, crossed >= 0 && face != glm::dvec3(0.0) ? &face : nullptr);
            previous = v.front;
        } else {
            // Fig. 4.5: the plane's crossing inside [tIn, tOut] splits the segment; the material
            // met first is the front one when the ray runs against the normal.
            const glm::dvec3 n(v.normal);
            const glm::dvec3 centre = glm::dvec3(cell) + 0.5;
            const double dn = glm::dot(n, d);
            const double at = glm::dot(n, o - centre);  // n·(o − c); the plane is n·(x − c) = offset
            const bool frontFirst = dn <= 0.0;
            const float first = frontFirst ? v.front : v.back, second = frontFirst ? v.back : v.front;
            const double tPlane = std::abs(dn) < 1e-300 ? std::numeric_limits<double>::infinity() : (double(v.offset) - at) / dn;
            if (std::abs(dn) < 1e-300) {
                // Parallel to the plane: one material all the way, the side the ray runs on.
                go = add(at >= v.offset ? v.front : v.back, tIn, tOut, &n);
                previous = at >= v.offset ? v.front : v.back;
            } else if (tPlane <= tIn) {
                go = add(second, tIn, tOut, &n);
                previous = second;
            } else if (tPlane >= tOut) {
                go = add(first, tIn, tOut, &n);
                previous = first;
            } else {
                go = add(first, tIn, tPlane, &n) && add(second, tPlane, tOut, &n);
                previous = second;
            }
        }
        if (!go || tOut >= t1) break;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= int(dims[std::size_t(a)])) break;
        tNext[a] += tDelta[a];
        crossed = a;
        tIn = tOut;
    }
    return glm::vec4(accum);
}

RenderImage SplitVoxelRayCaster::render(const View& view) const {
    RenderImage img;
    img.width = view.width;
    img.height = view.height;
    img.rgba.assign(std::size_t(view.width) * view.height, glm::vec4(0.0f));
    img.depth.assign(img.rgba.size(), std::numeric_limits<float>::infinity());
    ThreadPool::shared().parallelFor(std::size_t(view.height), [&](std::size_t y0, std::size_t y1) {
        for (std::size_t y = y0; y < y1; ++y)
            for (int x = 0; x < view.width; ++x) {
                glm::dvec3 o, d;
                view.ray(x, double(y), o, d);
                const std::size_t i = y * std::size_t(view.width) + std::size_t(x);
                img.rgba[i] = cast(o, d, img.depth[i]);
            }
    }, 8);
    return img;
}

}  // namespace hvx::core
