#pragma once
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/octree/OctreeReader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/SpatialIndex.h"
#include "core/appearance/TransferFunction.h"
#include "core/camera/AccuracyFunction.h"
#include "core/camera/View.h"
#include "core/volume/CropBox.h"

namespace hvx::core {

struct WorkingSetOptions {
    std::size_t maxBricks = 2048;                  ///< GPU pool slots
    std::size_t uploadBytesPerFrame = 64u << 20;   ///< new slot contents per frame
    double voxelsPerPixel = 1.0;                   ///< accuracy target (larger is coarser)
    int finestLevel = 0;  ///< the cut goes no finer than this level (a level drawn whole: comparisons)
    CropBox crop;  ///< nodes outside it are neither refined nor loaded
    bool clip = false;
    glm::dvec4 clipPlane{0, 0, 1, 0};  ///< world plane; keeps points with dot(n, p) + d >= 0
    bool cullByTransferFunction = true;  ///< off for MIP/MinIP/average, where every value counts
    bool isosurface = false;
    double isoValue = 0.0;             ///< stored units
    std::uint32_t visibleRays = 1;     ///< a leaf hit by fewer rays last frame is invisible
    bool cpuMirror = true;  ///< keep float copies of pool slots for the CPU ray caster (off for GPU-only use)

    /// Takes what the crop box and the clip plane leave out (crop, clip) from another working
    /// set's options: a second volume drawn in the same view.
    void takeCullingOf(const WorkingSetOptions& o) {
        crop = o.crop;
        clip = o.clip;
        clipPlane = o.clipPlane;
    }
    bool sameCullingAs(const WorkingSetOptions& o) const {
        return crop.min == o.crop.min && crop.max == o.crop.max && clip == o.clip && clipPlane == o.clipPlane;
    }
};

/// Per frame, refines the cut of the octree (thesis ch. 2–3): from the root, nodes outside the
/// view frustums, empty under the transfer function (or not crossing the isovalue), clipped
/// away, or seen by no ray last frame are not refined further; the others are refined in order
/// of screen-space error until every node meets the accuracy target, the data is not in memory
/// yet (it is requested and the parent kept), or the brick pool is full. The cut becomes a
/// SpatialIndex whose leaves point at pool slots; pool slots are reused least recently used first,
/// and new slot contents are bounded per frame (upload budget). Requests per frame are bounded
/// by half the CPU cache, most urgent first: a cache smaller than what the view asks for would
/// otherwise evict bricks before the frame that asked for them takes them, and never settle.
///
/// Threading: frame thread only; loading happens in the BrickLoader's threads.
class WorkingSet {
public:
    WorkingSet(const OctreeReader& reader, BrickCache& cache, BrickLoader& loader, WorkingSetOptions options);

    struct FrameStats {
        double refineMs = 0;
        double levelsMs = 0;  ///< of refineMs, linking each leaf to its parent (SpatialIndex::linkParents)
        std::size_t blendingLeaves = 0;  ///< leaves that blend with coarser levels (SpatialIndex::blendingLeaves)
        std::size_t steepLeaves = 0;  ///< of those, where the level field reaches past what they sample (SpatialIndex::steepLeaves)
        bool indexRebuilt = false;  ///< the cut, a slot or a parent's slot changed: the index was built anew
        std::size_t cutNodes = 0, emptyLeaves = 0, requested = 0, uploads = 0, uploadBytes = 0, slotsUsed = 0;
        bool complete = false;  ///< every cut node met the target (nothing waited for data)
        int finestLevel = 0, coarsestLevel = 0;  ///< octree levels of the cut (0: full resolution)
        /// Nothing requested and nothing uploaded: the cut will not change while the view stays.
        bool settled() const { return requested == 0 && uploads == 0; }
    };
    /// Refines for these views; returns the index (valid until the next update()).
    const SpatialIndex& update(const std::vector<View>& views, const TransferFunction& tf,
                               const AccuracyFunction& accuracy = {});
    /// Synchronous mode (tests, the CLI, offline frames): refines and waits for the loader
    /// until the cut settles or `maxFrames` refinements have run; returns how many ran.
    int converge(const std::vector<View>& views, const TransferFunction& tf, const AccuracyFunction& accuracy = {},
                 int maxFrames = 64);
    /// Feedback: per index node ray counts from the frame just drawn with index().
    void setRayCounts(const std::vector<std::uint32_t>& countsPerIndexNode);
    const SpatialIndex& index() const { return index_; }
    /// Pool slot contents as float samples (edge^3 each); the CPU mirror of the GPU pool.
    const std::vector<std::shared_ptr<const std::vector<float>>>& slotData() const { return slotData_; }
    /// Pool slot contents as decoded bricks in their stored type (what the GPU pool uploads).
    const std::vector<std::shared_ptr<const Brick>>& slotBricks() const { return slotBricks_; }
    /// Slots whose contents changed in the last update (to upload to the GPU).
    const std::vector<std::uint32_t>& changedSlots() const { return changed_; }
    const FrameStats& stats() const { return stats_; }
    const OctreeSpace& space() const { return space_; }
    const std::vector<std::uint32_t>& cut() const { return cut_; }
    WorkingSetOptions& options() { return options_; }

private:
    bool skip(std::uint32_t node, const std::vector<glm::dmat4>& clips, const TransferFunction& tf) const;
    double error(std::uint32_t node, const std::vector<View>& views, const AccuracyFunction& accuracy) const;
    bool available(std::uint32_t node, double priority);
    /// The node's box in octree space (clipped to the volume's extent).
    void box(std::uint32_t node, glm::dvec3& lo, glm::dvec3& hi) const;
    void corners(std::uint32_t node, glm::dvec3 out[8]) const;

    const OctreeReader& reader_;
    BrickCache& cache_;
    BrickLoader& loader_;
    WorkingSetOptions options_;
    OctreeSpace space_;
    SpatialIndex index_;
    std::vector<std::uint32_t> cut_;
    // What index_ was built from: (cut node, its slot, its parent's slot) by node id.
    std::vector<glm::uvec3> indexKey_;
    std::unordered_set<std::uint32_t> keyAncestors_;  // scratch of the key's ancestors, kept for its buckets
    bool indexBuilt_ = false;
    std::vector<std::uint32_t> slotNode_;
    std::vector<std::uint64_t> slotStamp_;
    std::set<std::pair<std::uint64_t, std::uint32_t>> slotsByStamp_;  // least recently used first
    void stamp(std::uint32_t slot);
    std::vector<std::shared_ptr<const std::vector<float>>> slotData_;
    std::vector<std::shared_ptr<const Brick>> slotBricks_;
    std::unordered_map<std::uint32_t, std::uint32_t> nodeSlot_;
    std::vector<std::uint32_t> changed_;
    std::vector<char> invisible_;
    std::uint64_t frame_ = 0;
    std::size_t uploadLeft_ = 0;
    std::size_t requestLeft_ = 0;  // bytes this frame may still ask the loader for
    std::size_t brickBytes_ = 0;   // a decoded brick of the stored type, at most
    FrameStats stats_;
};

}  // namespace hvx::core
