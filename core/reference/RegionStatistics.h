#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/octree/OctreeReader.h"

namespace hvx::core {

/// A measurement region in patient space (LPS mm): a sphere, a box whose faces are
/// perpendicular to the patient axes, a disc (a circle drawn on a slice: a cylinder of radius
/// `radius` about `normal`, `thickness` mm thick, half-open along the normal ([-t/2, t/2)), so
/// one slice's voxels when it is the spacing, even midway between two),
/// an ellipse drawn on a slice (as the disc, with semi-axes `radius` along `axis` and `radius2`
/// along normal x axis), a polygon drawn on a slice (a prism of its outline along `normal`,
/// `thickness` mm thick; inside by the even-odd rule, so a freehand outline that crosses itself
/// is still a region), or a rectangle drawn on a slice (a polygon of four corners).
struct MeasureRegion {
    enum class Kind { Sphere, Box, Disc, Polygon, Ellipse, Rectangle } kind = Kind::Sphere;
    glm::dvec3 centre{0.0};  ///< sphere, disc, ellipse
    double radius = 0.0;     ///< sphere, disc, mm; an ellipse's semi-axis along `axis`
    double radius2 = 0.0;    ///< an ellipse's other semi-axis (along normal x axis), mm
    glm::dvec3 axis{1, 0, 0};        ///< ellipse: the unit direction of `radius`, in the plane
    glm::dvec3 low{0.0}, high{0.0};  ///< box corners (low < high on every axis)
    glm::dvec3 normal{0, 0, 1};      ///< disc, ellipse, polygon, rectangle; unit
    double thickness = 0.0;          ///< disc, ellipse, polygon, rectangle; mm
    std::vector<glm::dvec3> outline; ///< polygon, rectangle: its corners, on the plane through `centre`

    static MeasureRegion sphere(const glm::dvec3& centre, double radiusMm);
    static MeasureRegion box(const glm::dvec3& a, const glm::dvec3& b);
    static MeasureRegion disc(const glm::dvec3& centre, const glm::dvec3& normal, double radiusMm, double thicknessMm);
    /// A polygon through `outline`'s corners (projected on the plane through their mean, with
    /// `normal`); `centre` is that mean.
    static MeasureRegion polygon(const std::vector<glm::dvec3>& outline, const glm::dvec3& normal, double thicknessMm);
    /// An ellipse about `centre` in the plane of `normal`, semi-axis `a` mm along `axis` (made
    /// perpendicular to the normal) and `b` mm across.
    static MeasureRegion ellipse(const glm::dvec3& centre, const glm::dvec3& normal, const glm::dvec3& axis, double a,
                                 double b, double thicknessMm);
    /// The rectangle with opposite corners `from` and `to`, its sides along `axis` (made
    /// perpendicular to the normal) and normal x axis, in the plane of `normal` through `from`.
    static MeasureRegion rectangle(const glm::dvec3& from, const glm::dvec3& to, const glm::dvec3& normal,
                                   const glm::dvec3& axis, double thicknessMm);
    /// Whether the region is an outline of corners (a polygon or a rectangle).
    bool outlined() const { return kind == Kind::Polygon || kind == Kind::Rectangle; }
    /// The same region moved by `offset` mm.
    MeasureRegion movedBy(const glm::dvec3& offset) const;
    /// "sphere:X,Y,Z,R", "box:X0,Y0,Z0,X1,Y1,Z1", "disc:X,Y,Z,NX,NY,NZ,R,T" or
    /// "ellipse:X,Y,Z,NX,NY,NZ,AX,AY,AZ,A,B,T" (LPS mm); throws core::Error otherwise.
    static MeasureRegion parse(const std::string& text);
    bool contains(const glm::dvec3& p) const;
    std::string describe() const;
};

/// Statistics of the voxels whose centres lie in a region, in the volume's physical units (HU
/// for CT), read from the finest level of the octree (level 0), never from a coarser level or
/// what a view shows. Voxels of bricks stored without their values (empty below a threshold,
/// or lossy 8-bit) are counted apart: then `exact` is false and `note` says why. A region that
/// reaches outside the volume counts its voxels inside it, and `note` says so. So does a CT region
/// holding voxels at -1024 HU, which may be padding outside the scanned field (atPaddingValue).
struct RegionStatistics {
    std::uint64_t voxels = 0;
    double mean = 0, sd = 0, min = 0, max = 0;  ///< physical units; sd is the population SD
    double volumeMm3 = 0;                       ///< voxels times one voxel's volume
    double areaMm2 = 0;                         ///< a region drawn on a slice: volumeMm3 over its thickness
    std::uint64_t approximateVoxels = 0;        ///< in empty or lossy bricks
    /// CT in HU: voxels at exactly -1024 HU, the value Holovox gives pixels a series marks as
    /// padding (outside the scanned field) as well as air at the scale's floor: `note` says so.
    std::uint64_t atPaddingValue = 0;
    bool exact = true;
    std::string units;  ///< "HU" for CT, else empty
    std::string note;   ///< why the figures are not exact, why there are none, or that the region reaches outside the volume

    /// Throws core::Error when the region is degenerate (radius or a box side <= 0) or lies
    /// wholly outside the volume, and CorruptBrickError for a brick that cannot be read.
    static RegionStatistics compute(const OctreeReader& reader, const MeasureRegion& region);
};

}  // namespace hvx::core
