#include "core/reference/SplitVoxelRayCaster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "core/reference/PixelRays.h"
#include "core/reference/SplitCellMarch.h"

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
    SplitCompositor out{tf_, settings_, labels_, cellNormalToWorld_, -glm::normalize(dw)};
    SplitMarchState state;
    const auto& dims = grid_.dims();
    marchSplitCells(o, d, t0, t1, glm::ivec3(int(dims[0]), int(dims[1]), int(dims[2])),
                    [&](const glm::ivec3& c) { return grid_.at(std::uint32_t(c.x), std::uint32_t(c.y), std::uint32_t(c.z)); },
                    out, state);
    depth = out.depth;
    return glm::vec4(out.accum);
}

RenderImage SplitVoxelRayCaster::render(const View& view) const {
    return castPixelRays(view, [this](const glm::dvec3& o, const glm::dvec3& d, float& depth) { return cast(o, d, depth); });
}

}  // namespace hvx::core
