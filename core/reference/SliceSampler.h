#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/streaming/BrickCache.h"
#include "core/octree/OctreeLayout.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/OctreeSpace.h"

namespace hvx::core {

/// A planar image through the volume in patient space (LPS mm): pixel (i, j) lies at
/// centre + (i + 0.5 - width/2)·pixelMm·right + (j + 0.5 - height/2)·pixelMm·down.
struct SlicePlane {
    enum class Orientation { Axial, Coronal, Sagittal };
    glm::dvec3 centre{0.0};
    glm::dvec3 right{1, 0, 0}, down{0, 1, 0};  ///< unit vectors
    double pixelMm = 1.0;
    int width = 256, height = 256;

    /// The standard radiological planes through `centre`: axial seen from the feet (patient
    /// left on the image right, anterior up), coronal seen from the front (left on the right,
    /// superior up), sagittal seen from the patient's left (anterior on the left, superior up).
    static SlicePlane standard(Orientation o, const glm::dvec3& centre, double pixelMm, int width, int height);
    /// A plane perpendicular to `normal` (any direction, not zero): the standard plane whose
    /// normal is nearest, tilted by the smallest rotation onto `normal`, so that it is seen as a
    /// reader expects that plane (a tilted axial stays an axial seen from the feet).
    static SlicePlane oblique(const glm::dvec3& normal, const glm::dvec3& centre, double pixelMm, int width,
                              int height);
    /// Orientation letters at the image's left, right, top and bottom edges ("R", "L", "A", ...).
    static std::array<const char*, 4> edgeLabels(Orientation o);
    /// The letters of this plane's edges for any tilt ("RA" where the edge lies between right
    /// and anterior), left, right, top, bottom.
    std::array<std::string, 4> edgeLabels() const;
    /// right x down: the unit normal, pointing away from the viewer.
    glm::dvec3 normal() const;
    /// Where a patient point projects on the image, in pixels from its top-left corner (a
    /// pixel's centre at +0.5); the inverse of patientAt.
    glm::dvec2 pixelOf(const glm::dvec3& patient) const;
    /// The patient point on the plane at image position `pixel` (pixels from the top-left corner).
    glm::dvec3 patientAt(const glm::dvec2& pixel) const;
};

/// How a thick slab combines the samples across its thickness.
enum class SlabMode { Mip, MinIp, Mean };

/// A sampled slice: stored values (NaN outside the volume) and the octree level read.
struct SliceImage {
    int width = 0, height = 0, level = 0;
    std::vector<float> values;
    double slabMm = 0;  ///< the thickness sampled (0: a thin slice)
    int slabSamples = 1;
    SlabMode slabMode = SlabMode::Mip;  ///< how a slab's samples were combined
};

/// Samples planes through an octree at the level whose voxels match the plane's pixels, reading
/// bricks through a brick cache (synchronously: a slice touches few bricks). Trilinear inside
/// each brick, border included; a label map's slices take the nearest voxel (a class is never
/// interpolated into its neighbour's).
///
/// Threading: one thread at a time per object (the cache itself is thread-safe).
class SliceSampler {
public:
    SliceSampler(const OctreeReader& reader, BrickCache& cache);
    /// The coarsest level whose voxel is no larger than `pixelMm` along any axis, so that a thin
    /// slice never averages acquired slices over more than a pixel's depth (an anisotropic
    /// volume's thick axis decides).
    int levelFor(double pixelMm) const;
    /// The value at a patient point (LPS mm) at `level` (trilinear; a label map's nearest
    /// voxel), NaN outside the volume.
    double valueAt(const glm::dvec3& patient, int level) const;
    /// Samples `plane` at levelFor(plane.pixelMm), or at `level` when given (>= 0).
    SliceImage sample(const SlicePlane& plane, int level = -1) const;
    /// A thick slab centred on `plane`: an odd number of samples, the plane itself among them,
    /// one level voxel apart along the normal within `thicknessMm`, combined by `mode` (NaN
    /// where no sample lies in the volume). A slab
    /// thicker than the volume's diagonal is clamped to it; a thickness <= 0, or a label map,
    /// throws core::Error.
    SliceImage sampleSlab(const SlicePlane& plane, double thicknessMm, SlabMode mode, int level = -1) const;
    /// This volume on `plane` as `base` (another volume's image of it) was sampled: a slab of the
    /// same thickness and mode, so that an overlay on a MIP is the overlay's MIP; a thin slice
    /// for a thin base and always for a label map (whose slab would make up classes).
    SliceImage sampleLike(const SlicePlane& plane, const SliceImage& base) const;
    const OctreeSpace& space() const { return space_; }

private:
    std::shared_ptr<const Brick> brick(std::uint32_t node) const;

    const OctreeReader& reader_;
    BrickCache& cache_;
    OctreeSpace space_;
    OctreeLayout layout_;
    mutable std::uint32_t lastNode_ = UINT32_MAX;  // the brick read last (neighbouring samples share it)
    mutable std::shared_ptr<const Brick> lastBrick_;
};

}  // namespace hvx::core
