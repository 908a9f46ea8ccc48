#include "core/reference/SliceSampler.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/base/Error.h"
#include "core/camera/OrbitCamera.h"

namespace hvx::core {

SlicePlane SlicePlane::standard(Orientation o, const glm::dvec3& centre, double pixelMm, int width, int height) {
    SlicePlane p;
    p.centre = centre;
    p.pixelMm = pixelMm;
    p.width = width;
    p.height = height;
    switch (o) {  // LPS: +x patient left, +y posterior, +z superior
    case Orientation::Axial: p.right = {1, 0, 0}, p.down = {0, 1, 0}; break;
    case Orientation::Coronal: p.right = {1, 0, 0}, p.down = {0, 0, -1}; break;
    case Orientation::Sagittal: p.right = {0, 1, 0}, p.down = {0, 0, -1}; break;
    }
    return p;
}

std::array<const char*, 4> SlicePlane::edgeLabels(Orientation o) {
    switch (o) {
    case Orientation::Axial: return {"R", "L", "A", "P"};
    case Orientation::Coronal: return {"R", "L", "S", "I"};
    case Orientation::Sagittal: break;
    }
    return {"A", "P", "S", "I"};
}

SlicePlane SlicePlane::oblique(const glm::dvec3& normal, const glm::dvec3& centre, double pixelMm, int width,
                               int height) {
    const double len = glm::length(normal);
    if (!(len > 0) || !std::isfinite(len)) throw Error("a slice plane needs a normal of non-zero length");
    glm::dvec3 n = normal / len;
    SlicePlane best;
    double bestDot = -1;
    for (const auto o : {Orientation::Axial, Orientation::Coronal, Orientation::Sagittal}) {
        const SlicePlane p = standard(o, centre, pixelMm, width, height);
        const double d = std::abs(glm::dot(p.normal(), n));
        if (d > bestDot) bestDot = d, best = p;
    }
    if (glm::dot(best.normal(), n) < 0) n = -n;  // a plane has no side: keep the standard's view
    // Rodrigues: the smallest rotation taking the standard's normal onto n.
    const glm::dvec3 from = best.normal();
    const glm::dvec3 axis = glm::cross(from, n);
    const double s = glm::length(axis), c = glm::dot(from, n);
    if (s > 1e-12) {
        const glm::dvec3 k = axis / s;
        const auto rotate = [&](const glm::dvec3& v) {
            return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1 - c);
        };
        best.right = glm::normalize(rotate(best.right));
        best.down = glm::normalize(rotate(best.down));
    }
    return best;
}

glm::dvec3 SlicePlane::normal() const { return glm::normalize(glm::cross(right, down)); }

glm::dvec2 SlicePlane::pixelOf(const glm::dvec3& patient) const {
    return {width / 2.0 + glm::dot(patient - centre, right) / pixelMm, height / 2.0 + glm::dot(patient - centre, down) / pixelMm};
}

glm::dvec3 SlicePlane::patientAt(const glm::dvec2& pixel) const {
    return centre + (pixel.x - width / 2.0) * pixelMm * right + (pixel.y - height / 2.0) * pixelMm * down;
}

std::array<std::string, 4> SlicePlane::edgeLabels() const {
    return {OrbitCamera::patientLabel(-right), OrbitCamera::patientLabel(right), OrbitCamera::patientLabel(-down),
            OrbitCamera::patientLabel(down)};
}

SliceSampler::SliceSampler(const OctreeReader& reader, BrickCache& cache)
    : reader_(reader), cache_(cache),
      space_(OctreeSpace::of(reader.geometry(), reader.brickSize(), reader.levelCount())),
      layout_(reader.geometry().dims, reader.brickSize()) {}

int SliceSampler::levelFor(double pixelMm) const {
    // A coarser level halves every axis: its voxel along the thickest one (the slice spacing of
    // an anisotropic volume) is what a thin slice would average across.
    const auto& s = reader_.geometry().spacing;
    const double largest = std::max({s.x, s.y, s.z});
    int level = 0;
    while (level + 1 < reader_.levelCount() && largest * std::pow(2.0, level + 1) <= pixelMm) ++level;
    return level;
}

std::shared_ptr<const Brick> SliceSampler::brick(std::uint32_t node) const {
    if (auto b = cache_.get(node)) return b;
    auto b = std::make_shared<const Brick>(reader_.readBrick(node));
    cache_.put(node, b);
    return b;
}

double SliceSampler::valueAt(const glm::dvec3& patient, int level) const {
    const auto& dims = layout_.levelDims(0);
    const auto& grid = layout_.levelNodes(level);
    const glm::dvec3 o(space_.patientToOctree * glm::dvec4(patient, 1.0));
    // Inside the volume's own voxels (level 0: a coarser level's count is rounded up, and its
    // last voxel reaches past the volume's edge, where nothing was acquired).
    const glm::dvec3 full = o * space_.rootVoxels - 0.5;
    for (int a = 0; a < 3; ++a)
        if (!(full[a] >= -0.5 && full[a] <= double(dims[std::size_t(a)]) - 0.5)) return std::numeric_limits<double>::quiet_NaN();
    // Level voxel coordinates, integers at voxel centres.
    const glm::dvec3 c = o * (space_.rootVoxels / double(1u << level)) - 0.5;
    const auto bs = double(reader_.brickSize());
    std::uint32_t n[3];
    for (int a = 0; a < 3; ++a)
        n[a] = std::min(grid[std::size_t(a)] - 1, std::uint32_t(std::max(0.0, std::floor(c[a] / bs))));
    const std::uint32_t node = layout_.nodeId(level, n[0], n[1], n[2]);
    if (node != lastNode_) {
        lastBrick_ = brick(node);
        lastNode_ = node;
    }
    const Brick& b = *lastBrick_;
    const int edge = int(reader_.brickEdge());
    // Sample coordinates inside the brick (border included); the border holds the neighbours
    // (replicated at the volume's edges), so trilinear never leaves it.
    glm::dvec3 u;
    for (int a = 0; a < 3; ++a) u[a] = std::clamp(c[a] - n[a] * bs + reader_.border(), 0.0, double(edge - 1));
    if (reader_.geometry().isLabel) {  // a label is a class: the nearest voxel's, never a blend of two classes
        const glm::ivec3 n0 = glm::min(glm::ivec3(glm::round(u)), glm::ivec3(edge - 1));
        return b.value(std::uint32_t(n0.x), std::uint32_t(n0.y), std::uint32_t(n0.z));
    }
    const glm::ivec3 i0 = glm::min(glm::ivec3(u), glm::ivec3(edge - 2));
    const glm::dvec3 f = u - glm::dvec3(i0);
    double v = 0;
    for (int k = 0; k < 8; ++k) {
        const int dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1;
        const double w = (dx ? f.x : 1 - f.x) * (dy ? f.y : 1 - f.y) * (dz ? f.z : 1 - f.z);
        if (w > 0) v += w * b.value(std::uint32_t(i0.x + dx), std::uint32_t(i0.y + dy), std::uint32_t(i0.z + dz));
    }
    return v;
}

SliceImage SliceSampler::sample(const SlicePlane& plane, int level) const {
    SliceImage out;
    out.width = plane.width;
    out.height = plane.height;
    out.level = level >= 0 ? std::min(level, reader_.levelCount() - 1) : levelFor(plane.pixelMm);
    out.values.resize(std::size_t(plane.width) * std::size_t(plane.height));
    for (int j = 0; j < plane.height; ++j)
        for (int i = 0; i < plane.width; ++i) {
            const glm::dvec3 p = plane.centre + (i + 0.5 - plane.width / 2.0) * plane.pixelMm * plane.right +
                                 (j + 0.5 - plane.height / 2.0) * plane.pixelMm * plane.down;
            out.values[std::size_t(j) * std::size_t(plane.width) + std::size_t(i)] = float(valueAt(p, out.level));
        }
    return out;
}

SliceImage SliceSampler::sampleSlab(const SlicePlane& plane, double thicknessMm, SlabMode mode, int level) const {
    if (!(thicknessMm > 0) || !std::isfinite(thicknessMm))
        throw Error("a slab needs a thickness above 0 mm (" + std::to_string(thicknessMm) + " given)");
    if (reader_.geometry().isLabel)
        throw Error("a label map has no slab: its MIP, MinIP or mean would make up classes that are not there");
    const int lvl = level >= 0 ? std::min(level, reader_.levelCount() - 1) : levelFor(plane.pixelMm);
    const auto& g = reader_.geometry();
    const glm::dvec3 extent = glm::dvec3(g.dims[0], g.dims[1], g.dims[2]) * g.spacing;
    thicknessMm = std::min(thicknessMm, glm::length(extent));  // thicker than the volume: all of it
    const double step = space_.minSpacing * std::pow(2.0, lvl);
    // An odd count, so the plane itself is one of the samples: a slab's MIP is never below its
    // thin slice, nor its MinIP above it.
    const int n = 2 * int(std::floor(thicknessMm / (2 * step) + 1e-9)) + 1;
    const glm::dvec3 normal = plane.normal();
    SliceImage out;
    std::vector<double> acc;  // max, min or sum of the samples in the volume
    std::vector<int> count;
    for (int s = 0; s < n; ++s) {
        SlicePlane p = plane;
        p.centre += normal * ((s - (n - 1) / 2.0) * step);
        SliceImage one = sample(p, lvl);
        if (s == 0) {
            acc.assign(one.values.size(), 0.0);
            count.assign(one.values.size(), 0);
        }
        for (std::size_t i = 0; i < one.values.size(); ++i) {
            const double v = one.values[i];
            if (std::isnan(v)) continue;
            double& a = acc[i];
            if (count[i]++ == 0) a = v;
            else if (mode == SlabMode::Mip) a = std::max(a, v);
            else if (mode == SlabMode::MinIp) a = std::min(a, v);
            else a += v;
        }
        if (s == 0) out = std::move(one);
    }
    for (std::size_t i = 0; i < out.values.size(); ++i)
        out.values[i] = count[i] == 0 ? std::numeric_limits<float>::quiet_NaN()
                                      : float(mode == SlabMode::Mean ? acc[i] / count[i] : acc[i]);
    out.slabMm = thicknessMm;
    out.slabSamples = n;
    out.slabMode = mode;
    return out;
}

SliceImage SliceSampler::sampleLike(const SlicePlane& plane, const SliceImage& base) const {
    if (base.slabMm > 0 && !reader_.geometry().isLabel) return sampleSlab(plane, base.slabMm, base.slabMode);
    return sample(plane);
}

}  // namespace hvx::core
