#include "ui/CropBoxHandles.h"

#include <QPainter>
#include <QPen>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace hvx::ui {

CropBoxHandles::CropBoxHandles(const core::OctreeSpace& space, const std::array<std::uint32_t, 3>& dims, Project project,
                               Unproject unproject)
    : space_(space), dims_(dims), project_(std::move(project)), unproject_(std::move(unproject)) {}

glm::dvec3 CropBoxHandles::patient(const glm::dvec3& fraction) const {
    return glm::dvec3(space_.octreeToPatient * glm::dvec4(fraction * space_.extent, 1.0));
}

namespace {
/// The middle of a face of the box, in fractions of the volume's extent.
glm::dvec3 faceFraction(const core::CropBox& box, int face) {
    glm::dvec3 f = (box.min + box.max) * 0.5;
    f[face % 3] = face < 3 ? box.min[face % 3] : box.max[face % 3];
    return f;
}
}  // namespace

glm::dvec3 CropBoxHandles::faceCentre(const core::CropBox& box, int face) const { return patient(faceFraction(box, face)); }

std::optional<int> CropBoxHandles::faceAt(const core::CropBox& box, QPointF pos, double px) const {
    std::optional<int> best;
    double bestPx = px;
    for (int face = 0; face < 6; ++face) {
        const auto at = project_(faceCentre(box, face));
        if (!at) continue;
        const double d = std::hypot(at->x() - pos.x(), at->y() - pos.y());
        if (d < bestPx) bestPx = d, best = face;
    }
    return best;
}

core::CropBox CropBoxHandles::dragged(const core::CropBox& box, int face, QPointF from, QPointF to) const {
    const int a = face % 3;
    const bool low = face < 3;
    // The face's axis as a line through its centre: P(t) = p0 + t * step, t in fractions of the
    // volume; where a mouse ray passes nearest it gives the fraction under the mouse.
    glm::dvec3 g = faceFraction(box, face);
    const glm::dvec3 p0 = patient(g);
    g[a] += 1.0;
    const glm::dvec3 step = patient(g) - p0;
    const auto along = [&](QPointF pos) -> std::optional<double> {
        const auto [o, d] = unproject_(pos);
        const glm::dvec3 w = p0 - o;
        const double aa = glm::dot(step, step), b = glm::dot(step, d), c = glm::dot(d, d);
        const double denom = aa * c - b * b;
        if (denom < 1e-6 * aa * c) return std::nullopt;  // the axis points at the eye: the mouse cannot say how far
        return (b * glm::dot(d, w) - c * glm::dot(step, w)) / denom;
    };
    const auto t0 = along(from), t1 = along(to);
    if (!t0 || !t1) return box;
    const double delta = *t1 - *t0;
    // Faces on voxel boundaries (the box keeps whole voxels), at least one voxel apart.
    const double n = double(std::max<std::uint32_t>(1, dims_[std::size_t(a)]));
    const auto snap = [n](double x) { return std::round(x * n) / n; };
    core::CropBox out = box;
    if (low) out.min[a] = std::clamp(snap(box.min[a] + delta), 0.0, std::max(0.0, box.max[a] - 1.0 / n));
    else out.max[a] = std::clamp(snap(box.max[a] + delta), std::min(1.0, box.min[a] + 1.0 / n), 1.0);
    return out;
}

void CropBoxHandles::paint(QPainter& p, const core::CropBox& box) const {
    const QColor colour(255, 210, 80);
    p.setPen(QPen(colour, 1.2));
    p.setBrush(Qt::NoBrush);
    const auto corner = [&](int c) {
        return patient({(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y, (c & 4) ? box.max.z : box.min.z});
    };
    for (int c = 0; c < 8; ++c)
        for (int bit : {1, 2, 4}) {
            if (c & bit) continue;  // each edge once: from the corner with the bit clear
            const auto a = project_(corner(c)), b = project_(corner(c | bit));
            if (a && b) p.drawLine(*a, *b);
        }
    p.setBrush(QColor(0, 0, 0, 160));
    for (int face = 0; face < 6; ++face)
        if (const auto at = project_(faceCentre(box, face))) p.drawRect(QRectF(at->x() - 4, at->y() - 4, 8, 8));
    p.setBrush(Qt::NoBrush);
}

}  // namespace hvx::ui
