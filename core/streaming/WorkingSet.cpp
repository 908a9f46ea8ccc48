#include "core/streaming/WorkingSet.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include <glm/geometric.hpp>

namespace hvx::core {

WorkingSet::WorkingSet(const OctreeReader& reader, BrickCache& cache, BrickLoader& loader, WorkingSetOptions options)
    : reader_(reader), cache_(cache), loader_(loader), options_(options),
      space_(OctreeSpace::of(reader.geometry(), reader.brickSize(), reader.levelCount())) {
    invisible_.assign(reader.nodes().size(), 0);
    brickBytes_ = std::size_t(reader.brickEdge()) * reader.brickEdge() * reader.brickEdge() *
                  scalarSize(reader.geometry().scalarType);
}

void WorkingSet::box(std::uint32_t node, glm::dvec3& lo, glm::dvec3& hi) const {
    const auto& n = reader_.nodes()[node];
    const double size = std::ldexp(1.0, -(reader_.levelCount() - 1 - n.level));
    lo = glm::dvec3(n.x, n.y, n.z) * size;
    hi = glm::min(lo + size, space_.extent);
}

void WorkingSet::corners(std::uint32_t node, glm::dvec3 out[8]) const {
    glm::dvec3 lo, hi;
    box(node, lo, hi);
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
        out[c] = glm::dvec3(space_.octreeToPatient * glm::dvec4(p, 1.0));
    }
}

bool WorkingSet::skip(std::uint32_t node, const std::vector<glm::dmat4>& clips, const TransferFunction& tf) const {
    const auto& n = reader_.nodes()[node];
    if (options_.isosurface) {
        if (options_.isoValue < n.minValue || options_.isoValue > n.maxValue) return true;
    } else if (options_.cullByTransferFunction && tf.isEmpty(n.minValue, n.maxValue)) {
        return true;
    }
    if (!options_.crop.whole()) {  // the node's box in octree space against the crop box
        glm::dvec3 lo, hi;
        box(node, lo, hi);
        const glm::dvec3 cropLo = options_.crop.min * space_.extent, cropHi = options_.crop.max * space_.extent;
        for (int a = 0; a < 3; ++a)
            if (hi[a] <= cropLo[a] || lo[a] >= cropHi[a]) return true;
    }
    glm::dvec3 c[8];
    corners(node, c);
    if (options_.clip) {
        bool kept = false;
        for (const auto& p : c) kept = kept || glm::dot(glm::dvec3(options_.clipPlane), p) + options_.clipPlane.w >= 0;
        if (!kept) return true;
    }
    // Outside every view frustum: all corners beyond one clip plane of each view.
    bool insideSome = clips.empty();
    for (const auto& m : clips) {
        int out[6] = {0, 0, 0, 0, 0, 0};
        for (const auto& p : c) {
            const glm::dvec4 q = m * glm::dvec4(p, 1.0);
            out[0] += q.x < -q.w;
            out[1] += q.x > q.w;
            out[2] += q.y < -q.w;
            out[3] += q.y > q.w;
            out[4] += q.z < -q.w;
            out[5] += q.z > q.w;
        }
        bool outside = false;
        for (int k = 0; k < 6; ++k) outside = outside || out[k] == 8;
        insideSome = insideSome || !outside;
    }
    return !insideSome;
}

double WorkingSet::error(std::uint32_t node, const std::vector<View>& views, const AccuracyFunction& accuracy) const {
    glm::dvec3 c[8];
    corners(node, c);
    glm::dvec3 centre(0.0);
    for (const auto& p : c) centre += p / 8.0;
    const double radius = glm::length(c[7] - c[0]) / 2.0;
    const double voxel = space_.voxelSize(reader_.nodes()[node].level);
    double allowed = 1e300;
    for (const auto& v : views) {
        // The node's point nearest the eye, conservatively.
        const glm::dvec3 toEye = v.eye - centre;
        const double d = glm::length(toEye);
        const glm::dvec3 p = d > radius ? centre + toEye / d * radius : v.eye;
        allowed = std::min(allowed, accuracy ? accuracy(v, p) : options_.voxelsPerPixel * v.pixelFootprint(p));
    }
    return voxel / std::max(allowed, 1e-9);
}

void WorkingSet::stamp(std::uint32_t slot) {
    slotsByStamp_.erase({slotStamp_[slot], slot});
    slotStamp_[slot] = frame_;
    slotsByStamp_.insert({frame_, slot});
}

bool WorkingSet::available(std::uint32_t node, double priority) {
    auto it = nodeSlot_.find(node);
    if (it != nodeSlot_.end()) {
        stamp(it->second);
        return true;
    }
    auto brick = cache_.get(node);
    if (!brick) {
        if (requestLeft_ < brickBytes_) return false;  // asked again next frame, if still needed
        requestLeft_ -= brickBytes_;
        loader_.request(node, priority);
        ++stats_.requested;
        return false;
    }
    const std::size_t bytes = brick->data.size();
    if (bytes > uploadLeft_) return false;
    // A free slot, or the least recently used one not used this frame.
    std::uint32_t slot;
    if (slotNode_.size() < options_.maxBricks) {
        slot = std::uint32_t(slotNode_.size());
        slotNode_.push_back(SpatialIndex::kNone);
        slotStamp_.push_back(0);
        slotsByStamp_.insert({0, slot});
        slotData_.push_back(nullptr);
        slotBricks_.push_back(nullptr);
    } else {
        slot = slotsByStamp_.begin()->second;  // least recently used
        if (slotStamp_[slot] == frame_) return false;  // pool full of this frame's bricks
        nodeSlot_.erase(slotNode_[slot]);
    }
    std::shared_ptr<std::vector<float>> samples;
    if (options_.cpuMirror && brick->splitVoxels) {
        // Split-voxel cells, six floats each: front, back, the plane's normal and offset.
        samples = std::make_shared<std::vector<float>>(std::size_t(brick->edge) * brick->edge * brick->edge * 6);
        for (std::uint32_t z = 0, i = 0; z < brick->edge; ++z)
            for (std::uint32_t y = 0; y < brick->edge; ++y)
                for (std::uint32_t x = 0; x < brick->edge; ++x) {
                    const SplitVoxel v = brick->cell(x, y, z);
                    for (const float f : {v.front, v.back, v.normal.x, v.normal.y, v.normal.z, v.offset}) (*samples)[i++] = f;
                }
    } else if (options_.cpuMirror) {
        samples = std::make_shared<std::vector<float>>(std::size_t(brick->edge) * brick->edge * brick->edge);
        for (std::uint32_t z = 0, i = 0; z < brick->edge; ++z)
            for (std::uint32_t y = 0; y < brick->edge; ++y)
                for (std::uint32_t x = 0; x < brick->edge; ++x) (*samples)[i++] = float(brick->value(x, y, z));
    }
    slotNode_[slot] = node;
    stamp(slot);
    slotData_[slot] = std::move(samples);
    slotBricks_[slot] = brick;
    nodeSlot_[node] = slot;
    changed_.push_back(slot);
    uploadLeft_ -= bytes;
    ++stats_.uploads;
    stats_.uploadBytes += bytes;
    return true;
}

int WorkingSet::converge(const std::vector<View>& views, const TransferFunction& tf, const AccuracyFunction& accuracy,
                         int maxFrames) {
    int frames = 0;
    while (frames < maxFrames) {
        update(views, tf, accuracy);
        ++frames;
        if (stats_.settled()) break;
        loader_.waitIdle();
    }
    return frames;
}

const SpatialIndex& WorkingSet::update(const std::vector<View>& views, const TransferFunction& tf,
                                       const AccuracyFunction& accuracy) {
    const auto t0 = std::chrono::steady_clock::now();
    ++frame_;
    stats_ = {};
    changed_.clear();
    uploadLeft_ = options_.uploadBytesPerFrame;
    requestLeft_ = std::max(cache_.budget() / 2, brickBytes_);  // at least one brick
    loader_.beginFrame();
    std::vector<glm::dmat4> clips;
    for (const auto& v : views) clips.push_back(v.viewProjection());
    const auto& nodes = reader_.nodes();
    cut_.clear();
    bool complete = true;
    if (!skip(0, clips, tf) && available(0, 1e9)) {
        using Item = std::pair<double, std::uint32_t>;
        std::priority_queue<Item> heap;
        heap.push({error(0, views, accuracy), 0});
        while (!heap.empty()) {
            const auto [err, id] = heap.top();
            heap.pop();
            const auto& n = nodes[id];
            if (int(n.level) <= options_.finestLevel || err <= 1.0 || invisible_[id] || loader_.failed(id)) {
                cut_.push_back(id);
                continue;
            }
            std::vector<std::uint32_t> kept;
            for (std::uint32_t c = 0, o = 0; o < 8; ++o) {
                if (!(n.childMask & (1u << o))) continue;
                const std::uint32_t child = n.firstChild + c++;
                if (!skip(child, clips, tf)) kept.push_back(child);
            }
            if (cut_.size() + heap.size() + kept.size() > options_.maxBricks) {
                cut_.push_back(id);
                complete = false;
                continue;
            }
            bool ready = true;
            for (auto child : kept) ready = available(child, err) && ready;
            for (auto child : kept) ready = ready && !loader_.failed(child);
            if (!ready) {
                cut_.push_back(id);  // keep the parent while the children load
                complete = false;
                continue;
            }
            for (auto child : kept) heap.push({error(child, views, accuracy), child});
        }
    } else if (!skip(0, clips, tf)) {
        complete = false;
    }
    auto slotOf = [this](std::uint32_t id) {
        const auto it = nodeSlot_.find(id);
        return it == nodeSlot_.end() ? SpatialIndex::kNone : it->second;
    };
    std::vector<std::uint32_t> slots;
    slots.reserve(cut_.size());
    for (auto id : cut_) slots.push_back(slotOf(id));
    // The index depends on the set of cut nodes and their slots, and on their ancestors' slots
    // (multilevel sampling), not on the order refinement found them in: a view whose cut stays
    // keeps its index, and neither build nor linkParents runs. Key: (node, slot, 1) per cut
    // node, (node, slot, 0) per ancestor of one, by node.
    std::vector<glm::uvec3> key;
    key.reserve(cut_.size() + cut_.size() / 4);
    for (std::size_t i = 0; i < cut_.size(); ++i) key.push_back({cut_[i], slots[i], 1u});
    keyAncestors_.clear();
    for (auto id : cut_)
        for (auto up = nodes[id].parent; up != hvo::kNoNode && keyAncestors_.insert(up).second; up = nodes[up].parent)
            key.push_back({up, slotOf(up), 0u});
    std::sort(key.begin(), key.end(), [](const glm::uvec3& a, const glm::uvec3& b) { return a.x < b.x; });
    stats_.levelsMs = 0.0;
    stats_.indexRebuilt = !indexBuilt_ || key != indexKey_;
    if (stats_.indexRebuilt) {
        index_ = SpatialIndex::build(reader_, cut_, slots);
        // Every node refined this frame was resident this frame and keeps its slot: each leaf's
        // parent is there for multilevel sampling.
        const auto tLevels = std::chrono::steady_clock::now();
        index_.linkParents(reader_, slotOf);
        stats_.levelsMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tLevels).count();
        indexKey_ = std::move(key);
        indexBuilt_ = true;
    }
    stats_.blendingLeaves = index_.blendingLeaves;
    stats_.steepLeaves = index_.steepLeaves;
    stats_.cutNodes = cut_.size();
    stats_.finestLevel = reader_.levelCount() - 1;
    stats_.coarsestLevel = 0;
    for (auto id : cut_) {
        stats_.finestLevel = std::min(stats_.finestLevel, int(nodes[id].level));
        stats_.coarsestLevel = std::max(stats_.coarsestLevel, int(nodes[id].level));
    }
    stats_.emptyLeaves = index_.leafCount() - cut_.size();
    stats_.slotsUsed = slotNode_.size();
    stats_.complete = complete;
    stats_.refineMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return index_;
}

void WorkingSet::setRayCounts(const std::vector<std::uint32_t>& counts) {
    std::fill(invisible_.begin(), invisible_.end(), 0);
    // Leaves of the last index with too few rays are invisible; a node is invisible only if
    // every one of its indexed children is.
    std::vector<char> seen(index_.nodes.size(), 0);
    for (std::size_t i = index_.nodes.size(); i-- > 0;) {
        const auto& nd = index_.nodes[i];
        bool visible;
        if (nd.y & SpatialIndex::kLeafBit) {
            visible = nd.x == SpatialIndex::kNone || (i < counts.size() && counts[i] >= options_.visibleRays);
        } else {
            visible = false;
            for (std::uint32_t c = 0; c < 8; ++c) visible = visible || seen[nd.x + c];
        }
        seen[i] = visible;
        if (!visible && nd.z != SpatialIndex::kNone) invisible_[nd.z] = 1;
    }
}

}  // namespace hvx::core
