#include "core/streaming/ContentBox.h"

#include <algorithm>

#include <glm/mat4x4.hpp>

namespace hvx::core {

std::optional<ContentBox> ContentBox::of(const OctreeReader& reader, const TransferFunction& tf, bool everyValue,
                                         std::size_t maxNodes) {
    const auto& nodes = reader.nodes();
    // The finest level with at most maxNodes nodes: the box is exact to that level's bricks.
    std::vector<std::size_t> perLevel(std::size_t(reader.levelCount()), 0);
    for (const auto& n : nodes) ++perLevel[std::min<std::size_t>(n.level, perLevel.size() - 1)];
    int level = reader.levelCount() - 1;
    for (int l = 0; l < reader.levelCount(); ++l)
        if (perLevel[std::size_t(l)] <= maxNodes) {
            level = l;
            break;
        }
    const auto& g = reader.geometry();
    const double brick = double(reader.brickSize()) * double(1u << level);  // level-0 voxels per node edge
    std::optional<ContentBox> box;
    for (const auto& n : nodes) {
        if (n.level != level || (n.flags & hvo::NodeEmpty) || n.payloadOffset == 0) continue;
        if (!everyValue && tf.isEmpty(n.minValue, n.maxValue)) continue;
        const glm::dvec3 lo = glm::dvec3(n.x, n.y, n.z) * brick;
        const glm::dvec3 hi = glm::min(lo + brick, glm::dvec3(g.dims[0], g.dims[1], g.dims[2]));
        if (!box) box = ContentBox{lo, hi};
        box->lo = glm::min(box->lo, lo);
        box->hi = glm::max(box->hi, hi);
    }
    return box;
}

std::vector<glm::dvec3> ContentBox::corners(const VolumeGeometry& g) const {
    const glm::dmat4 toPatient = g.indexToPatient();
    std::vector<glm::dvec3> out;
    for (int c = 0; c < 8; ++c) {
        // Voxel centres sit at integer indices: the box's outer faces are half a voxel out.
        const glm::dvec3 i((c & 1) ? hi.x - 0.5 : lo.x - 0.5, (c & 2) ? hi.y - 0.5 : lo.y - 0.5,
                           (c & 4) ? hi.z - 0.5 : lo.z - 0.5);
        out.push_back(glm::dvec3(toPatient * glm::dvec4(i, 1.0)));
    }
    return out;
}

DisplayModel::Framing ContentBox::framing(const DisplayModel& display, const OctreeReader& reader, const TransferFunction& tf,
                                          bool everyValue, const glm::dvec3& right, const glm::dvec3& up, bool trueDepth,
                                          bool* found) {
    const auto& g = reader.geometry();
    const auto content = of(reader, tf, everyValue);
    if (found) *found = content.has_value();
    const ContentBox box = content ? *content : ContentBox{glm::dvec3(0.0), glm::dvec3(g.dims[0], g.dims[1], g.dims[2])};
    return display.frame(box.corners(g), right, up, trueDepth);
}

}  // namespace hvx::core
