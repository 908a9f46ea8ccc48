#include "ui/VolumeViewScene.h"

#include <algorithm>

#include "core/base/Error.h"

namespace hvx::ui {

using volume_view::applyMode;
using volume_view::kCacheBytes;

std::unique_ptr<VolumeView::Scene> VolumeView::makeScene(std::shared_ptr<const core::OctreeReader> reader,
                                                         std::size_t cacheBytes) const {
    core::WorkingSetOptions options;
    options.cpuMirror = false;
    options.voxelsPerPixel = accuracy_;
    return std::make_unique<Scene>(std::move(reader), options, cacheBytes);
}

void VolumeView::setVolume(std::shared_ptr<const core::OctreeReader> reader, bool keepCamera) {
    keepCamera = keepCamera && scene_ != nullptr;
    fused_.reset();
    split_.reset();
    splitShown_ = false;
    scene_.reset();
    times_.clear();
    timePoint_ = -1;
    error_.clear();
    if (reader) {
        scene_ = makeScene(std::move(reader), kCacheBytes);
        setRenderSettings(settings_);
        if (!keepCamera) resetView();
    }
    update();
}

void VolumeView::setTimePoints(std::vector<std::shared_ptr<const core::OctreeReader>> readers, int current) {
    if (readers.empty() || current < 0 || current >= int(readers.size()) || !readers[std::size_t(current)])
        throw core::Error("the time point shown must have an octree");
    const bool keepCamera = scene_ != nullptr;
    split_.reset();  // drawn from the series' own octrees
    splitShown_ = false;
    scene_.reset();
    times_.clear();
    times_.resize(readers.size());
    for (std::size_t i = 0; i < readers.size(); ++i) setTimePoint(int(i), std::move(readers[i]));
    scene_ = std::move(times_[std::size_t(current)]);
    timePoint_ = current;
    setRenderSettings(settings_);
    if (!keepCamera) resetView();
    update();
}

void VolumeView::setTimePoint(int index, std::shared_ptr<const core::OctreeReader> reader) {
    if (index < 0 || index >= int(times_.size()) || index == timePoint_ || !reader) return;
    // Every time point keeps its bricks: the view's budget shared among them.
    times_[std::size_t(index)] = makeScene(std::move(reader), std::max(kCacheBytes / times_.size(), std::size_t(64) << 20));
    applyMode(times_[std::size_t(index)]->ws.options(), settings_);
}

bool VolumeView::showTimePoint(int index) {
    if (index < 0 || index >= int(times_.size())) return false;
    if (index == timePoint_) return true;
    if (!times_[std::size_t(index)]) return false;
    times_[std::size_t(timePoint_)] = std::move(scene_);
    scene_ = std::move(times_[std::size_t(index)]);
    timePoint_ = index;
    setRenderSettings(settings_);
    update();
    return true;
}

void VolumeView::prefetchNeighbours() {
    if (times_.empty() || !tf_) return;
    const int n = int(times_.size());
    for (const int next : {(timePoint_ + 1) % n, (timePoint_ + n - 1) % n}) {
        auto& scene = times_[std::size_t(next)];
        if (!scene) continue;
        // Refined for this very view and settled: nothing more to ask of it (a still view does
        // not refine its neighbours frame after frame).
        const auto& before = scene->prefetchedFor;
        const auto &mine = scene->ws.options(), &shown = scene_->ws.options();
        const bool sameOptions = mine.sameCullingAs(shown);
        if (before && sameOptions && scene->ws.stats().settled() && before->sameCamera(lastView_)) continue;
        scene->prefetchedFor = lastView_;
        scene->ws.options().takeCullingOf(scene_->ws.options());
        scene->ws.update({lastView_}, *tf_);  // requests what that frame will need; the loader reads it meanwhile
    }
}

std::size_t VolumeView::bricksLoaded() const {
    std::size_t n = scene_ ? scene_->loader.loadedCount() : 0;
    for (const auto& t : times_)
        if (t) n += t->loader.loadedCount();
    return n;
}

void VolumeView::setFusedVolume(std::shared_ptr<const core::OctreeReader> reader, const core::TransferFunction& tf) {
    if (!reader) return clearFusedVolume();
    if (!fused_ || fused_->reader != reader) fused_ = makeScene(std::move(reader), kCacheBytes);
    fusedTf_ = std::make_unique<core::TransferFunction>(tf);
    update();
}

void VolumeView::setSplitVolume(std::shared_ptr<const core::OctreeReader> reader) {
    if (!reader) {
        split_.reset();
        splitShown_ = false;
    } else if (!split_ || split_->reader != reader) {
        if (!reader->splitVoxels()) throw core::Error(reader->path() + " is not a split-voxel octree");
        split_.reset();
        splitShown_ = false;
        split_ = makeScene(std::move(reader), kCacheBytes);
        applyMode(split_->ws.options(), settings_);
    }
    update();
}

void VolumeView::clearFusedVolume() {
    if (!fused_) return;
    fused_.reset();
    fusedTf_.reset();
    update();
}

}  // namespace hvx::ui
