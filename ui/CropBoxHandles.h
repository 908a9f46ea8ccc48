#pragma once
#include <QPointF>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>

#include <glm/vec3.hpp>

#include "core/streaming/OctreeSpace.h"
#include "core/volume/CropBox.h"

class QPainter;

namespace hvx::ui {

/// The crop box as the 3D view draws and drags it: its twelve edges (a wireframe over the
/// volume) and a handle at the middle of each of its six faces; dragging a face's handle moves
/// that face along its own axis to where the mouse's ray passes nearest that axis (exact under
/// perspective), to the nearest voxel boundary, never past the volume nor closer than one voxel
/// to the opposite face.
///
/// Threading: GUI thread (plain state, no Qt objects).
class CropBoxHandles {
public:
    /// Widget position of a patient point, or none when it lies behind the eye.
    using Project = std::function<std::optional<QPointF>(const glm::dvec3&)>;
    /// The ray (origin, unit direction; patient coordinates) through a widget position.
    using Unproject = std::function<std::pair<glm::dvec3, glm::dvec3>(QPointF)>;
    /// `space`: the volume's octree space (the box's fractions are of its extent); `dims`: its
    /// voxels along i, j, k.
    CropBoxHandles(const core::OctreeSpace& space, const std::array<std::uint32_t, 3>& dims, Project project,
                   Unproject unproject);
    /// The middle of face `face` of `box` (0, 1, 2: the low i, j, k faces; 3, 4, 5: the high
    /// ones), in patient coordinates (LPS mm).
    glm::dvec3 faceCentre(const core::CropBox& box, int face) const;
    /// The face whose handle lies within `px` pixels of `pos`, the nearest one.
    std::optional<int> faceAt(const core::CropBox& box, QPointF pos, double px = 8.0) const;
    /// `box` with `face` moved by a mouse drag from `from` to `to` (widget positions).
    core::CropBox dragged(const core::CropBox& box, int face, QPointF from, QPointF to) const;
    /// The wireframe and the handles.
    void paint(QPainter& p, const core::CropBox& box) const;

private:
    glm::dvec3 patient(const glm::dvec3& fraction) const;

    core::OctreeSpace space_;
    std::array<std::uint32_t, 3> dims_;
    Project project_;
    Unproject unproject_;
};

}  // namespace hvx::ui
