#include "ui/FusionLink.h"

#include <algorithm>

#include "core/appearance/TransferFunction.h"
#include "core/base/Error.h"
#include "core/streaming/OctreeSpace.h"
#include "ui/SliceLayers.h"
#include "ui/VolumeView.h"

namespace hvx::ui {

FusionLink::FusionLink(SliceLayers& layers, VolumeView& view, QObject* parent)
    : QObject(parent), layers_(layers), view_(view) {
    connect(&layers_, &SliceLayers::changed, this, &FusionLink::apply);
    connect(&layers_, &SliceLayers::legendChanged, this, &FusionLink::apply);
}

void FusionLink::setEnabled(bool on) {
    enabled_ = on;
    apply();
}

void FusionLink::apply() {
    const bool labels = layers_.hasLabels();
    const auto reader = labels ? layers_.labelsReader() : layers_.overlayReader();
    if (!enabled_ || !layers_.base() || !reader) {
        shown_.clear();
        view_.clearFusedVolume();
        return;
    }
    const auto& g = reader->geometry();
    const double referenceLength = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount()).minSpacing;
    try {
        if (labels) {
            view_.setFusedVolume(reader, core::TransferFunction::forLabels(layers_.labelTable(), layers_.labelOpacity(),
                                                                           referenceLength));
            shown_ = tr("labels %1").arg(layers_.labelsName());
        } else {
            // The overlay's window is in physical units; its transfer function runs over stored values.
            const auto& w = layers_.overlayWindow();
            const double lo = (w.centre - w.width / 2 - g.rescaleIntercept) / g.rescaleSlope;
            const double hi = (w.centre + w.width / 2 - g.rescaleIntercept) / g.rescaleSlope;
                    view_.setFusedVolume(reader, core::TransferFunction::forColorMap(layers_.overlayMap(), lo, hi,
                                                                             layers_.overlayOpacity(), g.valueMin,
                                                                             g.valueMax, referenceLength));
            shown_ = tr("overlay %1").arg(layers_.overlayName());
        }
    } catch (const core::Error& e) {
        shown_.clear();
        view_.clearFusedVolume();
        emit failed(tr("The 3D view shows the open volume alone: %1").arg(QString::fromStdString(e.what())));
    }
}

}  // namespace hvx::ui
