#include "core/reference/RegionStatistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <utility>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"

namespace hvx::core {

MeasureRegion MeasureRegion::sphere(const glm::dvec3& centre, double radiusMm) {
    MeasureRegion r;
    r.kind = Kind::Sphere;
    r.centre = centre;
    r.radius = radiusMm;
    return r;
}

MeasureRegion MeasureRegion::box(const glm::dvec3& a, const glm::dvec3& b) {
    MeasureRegion r;
    r.kind = Kind::Box;
    r.low = glm::min(a, b);
    r.high = glm::max(a, b);
    return r;
}

namespace {
/// `v` of length 1, or zero when it has no length (refused when measured).
glm::dvec3 unitOrZero(const glm::dvec3& v) {
    const double len = glm::length(v);
    return len > 0 ? v / len : glm::dvec3(0.0);
}
}  // namespace

MeasureRegion MeasureRegion::disc(const glm::dvec3& centre, const glm::dvec3& normal, double radiusMm,
                                  double thicknessMm) {
    MeasureRegion r;
    r.kind = Kind::Disc;
    r.centre = centre;
    r.normal = unitOrZero(normal);
    r.radius = radiusMm;
    r.thickness = thicknessMm;
    return r;
}

MeasureRegion MeasureRegion::polygon(const std::vector<glm::dvec3>& outline, const glm::dvec3& normal, double thicknessMm) {
    MeasureRegion r;
    r.kind = Kind::Polygon;
    r.outline = outline;
    r.normal = unitOrZero(normal);
    r.thickness = thicknessMm;
    for (const auto& p : outline) r.centre += p / double(std::max<std::size_t>(1, outline.size()));
    return r;
}

MeasureRegion MeasureRegion::ellipse(const glm::dvec3& centre, const glm::dvec3& normal, const glm::dvec3& axis,
                                     double a, double b, double thicknessMm) {
    MeasureRegion r;
    r.kind = Kind::Ellipse;
    r.centre = centre;
    r.normal = unitOrZero(normal);
    r.axis = unitOrZero(axis - glm::dot(axis, r.normal) * r.normal);
    r.radius = a;
    r.radius2 = b;
    r.thickness = thicknessMm;
    return r;
}

MeasureRegion MeasureRegion::rectangle(const glm::dvec3& from, const glm::dvec3& to, const glm::dvec3& normal,
                                       const glm::dvec3& axis, double thicknessMm) {
    const glm::dvec3 n = unitOrZero(normal);
    const glm::dvec3 u = unitOrZero(axis - glm::dot(axis, n) * n), v = glm::cross(n, u);
    const glm::dvec3 d = to - from;
    const glm::dvec3 du = glm::dot(d, u) * u, dv = glm::dot(d, v) * v;
    MeasureRegion r = polygon({from, from + du, from + du + dv, from + dv}, n, thicknessMm);
    r.kind = Kind::Rectangle;
    return r;
}

MeasureRegion MeasureRegion::movedBy(const glm::dvec3& offset) const {
    MeasureRegion r = *this;
    r.centre += offset;
    r.low += offset;
    r.high += offset;
    for (auto& p : r.outline) p += offset;
    return r;
}

namespace {
/// Two unit axes spanning the plane perpendicular to `n`.
std::pair<glm::dvec3, glm::dvec3> planeAxes(const glm::dvec3& n) {
    const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(n, helper));
    return {u, glm::cross(n, u)};
}

/// Whether `p` lies inside the polygon (even-odd rule, in the plane's coordinates).
bool insidePolygon(const MeasureRegion& r, const glm::dvec3& p) {
    const auto [u, v] = planeAxes(r.normal);
    const double px = glm::dot(p - r.centre, u), py = glm::dot(p - r.centre, v);
    bool inside = false;
    const std::size_t n = r.outline.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const double xi = glm::dot(r.outline[i] - r.centre, u), yi = glm::dot(r.outline[i] - r.centre, v);
        const double xj = glm::dot(r.outline[j] - r.centre, u), yj = glm::dot(r.outline[j] - r.centre, v);
        if ((yi > py) != (yj > py) && px < (xj - xi) * (py - yi) / (yj - yi) + xi) inside = !inside;
    }
    return inside;
}
}  // namespace

MeasureRegion MeasureRegion::parse(const std::string& text) {
    const auto colon = text.find(':');
    const std::string kind = text.substr(0, colon);
    std::vector<double> v;
    if (colon != std::string::npos) {
        std::stringstream in(text.substr(colon + 1));
        for (std::string part; std::getline(in, part, ',');) {
            char* end = nullptr;
            const double x = std::strtod(part.c_str(), &end);
            // decimal numbers only (strtod also reads hex, "0x3" for 3); no empty field, none after a trailing comma
            const bool decimal = part.find_first_not_of("0123456789+-.eE ") == std::string::npos;
            if (part.empty() || !decimal || *end != '\0' || !std::isfinite(x) || text.back() == ',') {
                v.clear();
                break;
            }
            v.push_back(x);
        }
    }
    if (kind == "sphere" && v.size() == 4) return sphere({v[0], v[1], v[2]}, v[3]);
    if (kind == "box" && v.size() == 6) return box({v[0], v[1], v[2]}, {v[3], v[4], v[5]});
    if (kind == "disc" && v.size() == 8) return disc({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6], v[7]);
    if (kind == "ellipse" && v.size() == 12)
        return ellipse({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9], v[10], v[11]);
    throw Error("'" + text + "' is not a region: sphere:X,Y,Z,R, box:X0,Y0,Z0,X1,Y1,Z1, disc:X,Y,Z,NX,NY,NZ,R,T or "
                "ellipse:X,Y,Z,NX,NY,NZ,AX,AY,AZ,A,B,T (LPS mm)");
}

bool MeasureRegion::contains(const glm::dvec3& p) const {
    if (kind == Kind::Sphere) {
        const glm::dvec3 d = p - centre;
        return glm::dot(d, d) <= radius * radius;
    }
    if (kind == Kind::Disc) {
        const glm::dvec3 d = p - centre;
        const double along = glm::dot(d, normal);
        const glm::dvec3 across = d - along * normal;
        // Half-open along the normal: a slab one spacing thick takes one layer of voxels even
        // when it lies midway between two.
        return along >= -thickness / 2 && along < thickness / 2 && glm::dot(across, across) <= radius * radius;
    }
    if (kind == Kind::Ellipse) {
        const glm::dvec3 d = p - centre;
        const double along = glm::dot(d, normal);
        const double u = glm::dot(d, axis) / radius, v = glm::dot(d, glm::cross(normal, axis)) / radius2;
        return along >= -thickness / 2 && along < thickness / 2 && u * u + v * v <= 1.0;
    }
    if (outlined())
        return outline.size() >= 3 && glm::dot(p - centre, normal) >= -thickness / 2 &&
               glm::dot(p - centre, normal) < thickness / 2 && insidePolygon(*this, p);
    return p.x >= low.x && p.x <= high.x && p.y >= low.y && p.y <= high.y && p.z >= low.z && p.z <= high.z;
}

std::string MeasureRegion::describe() const {
    char buf[160];
    if (kind == Kind::Sphere)
        std::snprintf(buf, sizeof buf, "sphere of radius %.4g mm at (%.4g, %.4g, %.4g)", radius, centre.x, centre.y,
                      centre.z);
    else if (kind == Kind::Disc)
        std::snprintf(buf, sizeof buf, "disc of radius %.4g mm, %.4g mm thick, at (%.4g, %.4g, %.4g)", radius, thickness,
                      centre.x, centre.y, centre.z);
    else if (kind == Kind::Ellipse)
        std::snprintf(buf, sizeof buf, "ellipse of semi-axes %.4g and %.4g mm, %.4g mm thick, at (%.4g, %.4g, %.4g)",
                      radius, radius2, thickness, centre.x, centre.y, centre.z);
    else if (kind == Kind::Rectangle)
        std::snprintf(buf, sizeof buf, "rectangle %.4g by %.4g mm, %.4g mm thick, about (%.4g, %.4g, %.4g)",
                      glm::length(outline[1] - outline[0]), glm::length(outline[2] - outline[1]), thickness, centre.x,
                      centre.y, centre.z);
    else if (kind == Kind::Polygon)
        std::snprintf(buf, sizeof buf, "polygon of %zu corners, %.4g mm thick, about (%.4g, %.4g, %.4g)", outline.size(),
                      thickness, centre.x, centre.y, centre.z);
    else
        std::snprintf(buf, sizeof buf, "box (%.4g, %.4g, %.4g) to (%.4g, %.4g, %.4g)", low.x, low.y, low.z, high.x,
                      high.y, high.z);
    return buf;
}

RegionStatistics RegionStatistics::compute(const OctreeReader& reader, const MeasureRegion& region) {
    const auto& g = reader.geometry();
    const bool polygon = region.outlined();
    const bool ellipse = region.kind == MeasureRegion::Kind::Ellipse;
    if (region.kind == MeasureRegion::Kind::Rectangle && region.outline.size() != 4)
        throw Error("a rectangle needs four corners");
    if (polygon) {
        double area2 = 0, extent2 = 0;  // twice the signed area (shoelace), in the plane; the size squared
        const auto [u, v] = planeAxes(region.normal);
        for (std::size_t i = 0, n = region.outline.size(); i < n; ++i) {
            const glm::dvec3 a = region.outline[i] - region.centre, b = region.outline[(i + 1) % n] - region.centre;
            area2 += glm::dot(a, u) * glm::dot(b, v) - glm::dot(b, u) * glm::dot(a, v);
            extent2 = std::max(extent2, glm::dot(a, a));
        }
        // (Corners on one line leave a rounding error's worth of area.)
        const std::string name = region.kind == MeasureRegion::Kind::Rectangle ? "rectangle" : "polygon";
        if (region.outline.size() < 3 || !(std::abs(area2) > 1e-9 * extent2))
            throw Error(region.kind == MeasureRegion::Kind::Rectangle
                            ? std::string("the rectangle has no area: one of its sides has no length")
                            : "the polygon has no area: it needs three corners or more, not all on one line");
        if (!(region.thickness > 0) || !(glm::length(region.normal) > 0.5))
            throw Error("the " + name + " needs a thickness above 0 mm and a normal");
    }
    if (ellipse && (!(region.radius > 0) || !(region.radius2 > 0)))
        throw Error("the ellipse has no area (semi-axes " + std::to_string(region.radius) + " and " +
                    std::to_string(region.radius2) + " mm)");
    if (ellipse && (!(region.thickness > 0) || !(glm::length(region.normal) > 0.5) || !(glm::length(region.axis) > 0.5)))
        throw Error("the ellipse needs a thickness above 0 mm, a normal and an axis in its plane");
    if (region.kind != MeasureRegion::Kind::Box && !polygon && !ellipse && !(region.radius > 0))
        throw Error("the " + std::string(region.kind == MeasureRegion::Kind::Disc ? "disc" : "sphere") +
                    " has no volume (radius " + std::to_string(region.radius) + " mm)");
    if (region.kind == MeasureRegion::Kind::Disc && (!(region.thickness > 0) || !(glm::length(region.normal) > 0.5)))
        throw Error("the disc needs a thickness above 0 mm and a normal");
    if (region.kind == MeasureRegion::Kind::Box &&
        !(region.high.x > region.low.x && region.high.y > region.low.y && region.high.z > region.low.z))
        throw Error("the box has no volume: every side must be longer than 0 mm");
    // The region's patient-space bounding box, in voxel indices.
    // (A disc lies within the sphere through its rim.)
    const double across = ellipse ? std::max(region.radius, region.radius2) : region.radius;
    const double reach = region.kind == MeasureRegion::Kind::Disc || ellipse
                             ? std::sqrt(across * across + region.thickness * region.thickness / 4)
                             : region.radius;
    const bool round = region.kind != MeasureRegion::Kind::Box;
    glm::dvec3 lo = round ? region.centre - reach : region.low;
    glm::dvec3 hi = round ? region.centre + reach : region.high;
    if (polygon) {  // the corners' box, widened by half the thickness along the normal
        lo = hi = region.outline[0];
        for (const auto& p : region.outline) lo = glm::min(lo, p), hi = glm::max(hi, p);
        lo -= glm::abs(region.normal) * (region.thickness / 2);
        hi += glm::abs(region.normal) * (region.thickness / 2);
    }
    const glm::dmat4 toIndex = glm::inverse(g.indexToPatient());
    glm::dvec3 first(std::numeric_limits<double>::max()), last(std::numeric_limits<double>::lowest());
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
        const glm::dvec3 i(toIndex * glm::dvec4(corner, 1.0));
        first = glm::min(first, i);
        last = glm::max(last, i);
    }
    std::int64_t from[3], to[3];  // inclusive voxel ranges
    bool between = false;         // inside the volume, but around no voxel centre
    for (int a = 0; a < 3; ++a) {
        const double size = double(g.dims[std::size_t(a)]);
        if (std::isnan(first[a]) || std::isnan(last[a]))
            throw Error("the " + region.describe() + " is too large to place on the volume's grid");
        if (last[a] < -0.5 || first[a] > size - 0.5) throw Error("the " + region.describe() + " lies outside the volume");
        // Clamped before the conversion to integers: a region of 1e19 mm holds the whole volume.
        first[a] = std::max(first[a], -2.0);
        last[a] = std::min(last[a], size + 1.0);
        from[a] = std::max<std::int64_t>(0, std::int64_t(std::ceil(first[a] - 1e-9)));
        to[a] = std::min<std::int64_t>(std::int64_t(size) - 1, std::int64_t(std::floor(last[a] + 1e-9)));
        between = between || from[a] > to[a];
    }
    // A region that holds no voxel centre lies outside the volume, or overlaps only its edge,
    // when its centre lies outside (the box test above passes an oblique volume's corner, and a
    // region reaching less than half a voxel in), else between the centres.
    auto noVoxel = [&]() -> RegionStatistics {
        const glm::dvec3 c(toIndex * glm::dvec4(region.kind == MeasureRegion::Kind::Box ? 0.5 * (region.low + region.high)
                                                                                      : region.centre, 1.0));
        for (int a = 0; a < 3; ++a)
            if (c[a] < -0.5 || c[a] > double(g.dims[std::size_t(a)]) - 0.5)
                throw Error("the " + region.describe() + " holds no voxel centre: its centre lies outside the volume");
        RegionStatistics none;
        none.units = g.hounsfield() ? "HU" : "";
        none.exact = false;
        none.note = "no voxel centre lies in the " + region.describe() + " (it is smaller than a voxel)";
        return none;
    };
    const glm::dmat4 toPatient = g.indexToPatient();
    // Whether the region holds voxel centres of the grid continued past the volume's faces: then
    // it reaches outside, and only its part inside is counted.
    auto reachesOutside = [&] {
        std::int64_t a0[3], a1[3];  // the region's index range on the continued grid, one layer past each face at most
        for (int a = 0; a < 3; ++a) {
            a0[a] = std::max<std::int64_t>(-1, std::int64_t(std::ceil(first[a] - 1e-9)));
            a1[a] = std::min<std::int64_t>(std::int64_t(g.dims[std::size_t(a)]), std::int64_t(std::floor(last[a] + 1e-9)));
        }
        for (int a = 0; a < 3; ++a)
            for (const std::int64_t layer : {std::int64_t(-1), std::int64_t(g.dims[std::size_t(a)])}) {
                if (layer < a0[a] || layer > a1[a]) continue;
                const int b = (a + 1) % 3, c = (a + 2) % 3;
                for (std::int64_t u = a0[b]; u <= a1[b]; ++u)
                    for (std::int64_t v = a0[c]; v <= a1[c]; ++v) {
                        glm::dvec4 index(0.0, 0.0, 0.0, 1.0);
                        index[a] = double(layer);
                        index[b] = double(u);
                        index[c] = double(v);
                        if (region.contains(glm::dvec3(toPatient * index))) return true;
                    }
            }
        return false;
    };
    const std::int64_t bs = reader.brickSize();
    const std::int64_t border = reader.border();
    // Level-0 nodes by grid coordinate.
    std::int64_t grid[3];
    for (int a = 0; a < 3; ++a) grid[a] = (std::int64_t(g.dims[std::size_t(a)]) + bs - 1) / bs;
    std::vector<std::uint32_t> leaf(std::size_t(grid[0] * grid[1] * grid[2]), UINT32_MAX);
    const auto& nodes = reader.nodes();
    for (std::uint32_t n = 0; n < nodes.size(); ++n)
        if (nodes[n].level == 0)
            leaf[std::size_t((std::int64_t(nodes[n].z) * grid[1] + nodes[n].y) * grid[0] + nodes[n].x)] = n;

    RegionStatistics s;
    s.units = g.hounsfield() ? "HU" : "";
    if (between) return noVoxel();
    double mean = 0, m2 = 0;  // Welford's running mean and sum of squared deviations
    const bool hounsfield = g.hounsfield();
    std::uint64_t atPadding = 0;
    double minV = std::numeric_limits<double>::max(), maxV = std::numeric_limits<double>::lowest();
    bool lossy = false, empty = false;
    for (std::int64_t bz = from[2] / bs; bz <= to[2] / bs; ++bz)
        for (std::int64_t by = from[1] / bs; by <= to[1] / bs; ++by)
            for (std::int64_t bx = from[0] / bs; bx <= to[0] / bs; ++bx) {
                const std::uint32_t node = leaf[std::size_t((bz * grid[1] + by) * grid[0] + bx)];
                if (node == UINT32_MAX) throw Error(reader.path() + ": the octree has no brick at level 0 for " +
                                                    std::to_string(bx) + "," + std::to_string(by) + "," + std::to_string(bz));
                const Brick b = reader.readBrick(node);
                std::uint64_t inBrick = 0;
                for (std::int64_t k = std::max(from[2], bz * bs); k <= std::min(to[2], bz * bs + bs - 1); ++k)
                    for (std::int64_t j = std::max(from[1], by * bs); j <= std::min(to[1], by * bs + bs - 1); ++j)
                        for (std::int64_t i = std::max(from[0], bx * bs); i <= std::min(to[0], bx * bs + bs - 1); ++i) {
                            const glm::dvec3 p(toPatient * glm::dvec4(double(i), double(j), double(k), 1.0));
                            if (!region.contains(p)) continue;
                            const double stored = b.value(std::uint32_t(i - bx * bs + border),
                                                          std::uint32_t(j - by * bs + border),
                                                          std::uint32_t(k - bz * bs + border));
                            const double v = stored * g.rescaleSlope + g.rescaleIntercept;
                            const double delta = v - mean;
                            mean += delta / double(s.voxels + inBrick + 1);
                            m2 += delta * (v - mean);
                            minV = std::min(minV, v);
                            maxV = std::max(maxV, v);
                            atPadding += hounsfield && v == VolumeGeometry::kCtPaddingHu;
                            ++inBrick;
                        }
                s.voxels += inBrick;
                if (inBrick && (b.empty || b.lossy8)) {
                    s.approximateVoxels += inBrick;
                    lossy = lossy || b.lossy8;
                    empty = empty || b.empty;
                }
            }
    if (s.voxels == 0) return noVoxel();
    const double n = double(s.voxels);
    s.mean = mean;
    s.sd = std::sqrt(std::max(0.0, m2 / n));
    s.min = minV;
    s.max = maxV;
    const glm::dmat3 step(g.direction[0] * g.spacing.x, g.direction[1] * g.spacing.y, g.direction[2] * g.spacing.z);
    s.volumeMm3 = n * std::abs(glm::determinant(step));
    if (region.kind == MeasureRegion::Kind::Disc || polygon || ellipse) s.areaMm2 = s.volumeMm3 / region.thickness;
    if (s.approximateVoxels) {
        s.exact = false;
        s.note = std::to_string(s.approximateVoxels) + " of the voxels lie in bricks stored " +
                 (empty ? std::string("without their values (below the build's --empty-below)") : std::string()) +
                 (empty && lossy ? " or " : "") + (lossy ? std::string("as lossy 8-bit") : std::string()) +
                 ": the figures are approximate";
    }
    if (reachesOutside()) {  // the figures are those of the part inside, exact as such
        s.note += std::string(s.note.empty() ? "" : "; ") +
                  "the region reaches outside the volume: only the voxels inside the volume are counted";
    }
    if (atPadding) {  // the figures are exact; what the voxels stand for is not known
        s.atPaddingValue = atPadding;
        s.note += std::string(s.note.empty() ? "" : "; ") + std::to_string(atPadding) + " of the voxels are at exactly " +
                  "-1024 HU, the value pixels marked as padding (outside the scanned field) are given, as well as air " +
                  "at the scale's floor: where the region reaches past the scanned field, they are counted as air";
    }
    if (g.spacingAssumed) {
        s.exact = false;
        s.note += std::string(s.note.empty() ? "" : "; ") + "the pixel spacing is unknown (1 mm assumed): volume and "
                  "region are not in real mm";
    }
    return s;
}

}  // namespace hvx::core
