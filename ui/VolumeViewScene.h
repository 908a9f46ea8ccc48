#pragma once
// The 3D view's per-volume state (VolumeView::Scene) and what its translation units share:
// VolumeView.cpp (frames, input), VolumeViewScenes.cpp (volumes, time points, fused and
// split-voxel partners) and VolumeViewOffscreen.cpp (captures, comparisons, light-field frames).
#include <memory>
#include <optional>

#include "core/camera/View.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/RenderSettings.h"
#include "core/streaming/BrickCache.h"
#include "core/streaming/BrickLoader.h"
#include "core/streaming/OctreeSpace.h"
#include "core/streaming/WorkingSet.h"
#include "ui/VolumeView.h"

namespace hvx::ui {

/// Everything that belongs to one open volume, in construction order.
struct VolumeView::Scene {
    std::shared_ptr<const core::OctreeReader> reader;
    core::BrickCache cache;
    core::BrickLoader loader;
    core::WorkingSet ws;
    core::OctreeSpace space;
    std::optional<core::View> prefetchedFor;  // the view a neighbouring time point was last refined for
    Scene(std::shared_ptr<const core::OctreeReader> r, core::WorkingSetOptions options, std::size_t cacheBytes)
        : reader(std::move(r)), cache(cacheBytes), loader(*reader, cache), ws(*reader, cache, loader, options),
          space(core::OctreeSpace::of(reader->geometry(), reader->brickSize(), reader->levelCount())) {}
};

namespace volume_view {
inline constexpr std::size_t kCacheBytes = std::size_t(2) << 30;  // the view's brick cache budget

/// What the render mode asks of a working set: culling by the transfer function (DVR) or
/// the iso value's bricks alone.
inline void applyMode(core::WorkingSetOptions& o, const core::RenderSettings& settings) {
    o.cullByTransferFunction = settings.mode == core::RenderSettings::Mode::Dvr;
    o.isosurface = settings.mode == core::RenderSettings::Mode::Iso;
    o.isoValue = settings.isoValue;
}
}  // namespace volume_view

}  // namespace hvx::ui
