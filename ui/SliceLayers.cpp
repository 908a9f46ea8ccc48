#include "ui/SliceLayers.h"

#include <QFileInfo>

#include "core/base/Error.h"
#include "core/reference/SliceComposer.h"
#include "core/volume/FramePairing.h"

namespace hvx::ui {

struct SliceLayers::Layer {
    std::shared_ptr<const core::OctreeReader> reader;
    core::BrickCache cache{std::size_t(128) << 20};
    std::unique_ptr<core::SliceSampler> sampler;
    QString name;
    bool forced = false;
};

SliceLayers::SliceLayers(QObject* parent) : QObject(parent) {}
SliceLayers::~SliceLayers() = default;

std::unique_ptr<SliceLayers::Layer> SliceLayers::open(const QString& path, const QString& name, bool force,
                                                       QString& error) const {
    if (!base_) {
        error = tr("Open a volume first: a layer is laid over the open volume.");
        return nullptr;
    }
    auto layer = std::make_unique<Layer>();
    try {
        layer->reader = core::OctreeReader::open(path.toStdString());
    } catch (const core::Error& e) {
        error = QString::fromStdString(e.what());
        return nullptr;
    }
    layer->name = name.isEmpty() ? QFileInfo(path).fileName() : name;
    const auto pairing = core::FramePairing::of(base_->geometry(), baseName_.toStdString(), layer->reader->geometry(),
                                                layer->name.toStdString());
    if (pairing.refused && !force) {
        error = QString::fromStdString(pairing.sentence) + tr(". Tick \u201cin another frame\u201d to lay it over anyway.");
        return nullptr;
    }
    layer->forced = pairing.refused;
    layer->sampler = std::make_unique<core::SliceSampler>(*layer->reader, layer->cache);
    return layer;
}

void SliceLayers::setBase(std::shared_ptr<const core::OctreeReader> base, const QString& name) {
    base_ = std::move(base);
    baseName_ = name;
    note_.clear();
    for (auto* layer : {&overlay_, &labels_}) {
        if (!*layer) continue;
        const auto pairing = base_ ? core::FramePairing::of(base_->geometry(), name.toStdString(),
                                                            (*layer)->reader->geometry(), (*layer)->name.toStdString())
                                   : core::FramePairing{true, "no volume is open"};
        if (pairing.refused && !(*layer)->forced) {
            note_ = tr("%1 taken off: %2").arg((*layer)->name, QString::fromStdString(pairing.sentence));
            layer->reset();
        }
    }
    emit changed();
    emit legendChanged();
}

QString SliceLayers::setOverlay(const QString& path, const QString& name, bool force) {
    QString error;
    auto layer = open(path, name, force, error);
    if (!layer) return error;
    const auto& g = layer->reader->geometry();
    window_ = core::DisplayWindow::initial(g);
    note_ = QString::fromStdString(
        core::FramePairing::of(base_->geometry(), baseName_.toStdString(), g, layer->name.toStdString()).sentence);
    overlay_ = std::move(layer);
    emit changed();
    return {};
}

QString SliceLayers::setLabels(const QString& path, const QString& name, bool force) {
    QString error;
    auto layer = open(path, name, force, error);
    if (!layer) return error;
    const auto& g = layer->reader->geometry();
    if (!g.isLabel) return tr("%1 is not a label map (build it with --labels).").arg(layer->name);
    note_ = QString::fromStdString(
        core::FramePairing::of(base_->geometry(), baseName_.toStdString(), g, layer->name.toStdString()).sentence);
    labels_ = std::move(layer);
    // Its own table when it has one (an octree built from a DICOM SEG or RTSTRUCT keeps its
    // segments' names and colours beside it): another map's names would be wrong for it.
    // Without one, a table the user chose is kept (atlases sharing one LUT).
    const QString sidecar = QString::fromStdString(core::LabelTable::sidecarPath(path.toStdString()));
    if (QFileInfo::exists(sidecar) || tablePath_.isEmpty() || tablePath_ == sidecarTable_) {
        table_ = {};
        tablePath_.clear();
        sidecarTable_.clear();
        if (QFileInfo::exists(sidecar)) {
            try {
                table_ = core::LabelTable::load(sidecar.toStdString());
                tablePath_ = sidecarTable_ = sidecar;
            } catch (const core::Error& e) {
                note_ = QString::fromStdString(e.what());
            }
        }
    }
    notInTable_.clear();
    seen_.clear();
    emit changed();
    emit legendChanged();
    return {};
}

QString SliceLayers::setLabelTable(const QString& path) {
    core::LabelTable table;
    if (!path.isEmpty()) {
        try {
            table = core::LabelTable::load(path.toStdString());
        } catch (const core::Error& e) {
            return QString::fromStdString(e.what());
        }
    }
    table_ = std::move(table);
    tablePath_ = path;
    notInTable_.clear();
    emit changed();
    emit legendChanged();
    return {};
}

void SliceLayers::clearOverlay() {
    overlay_.reset();
    emit changed();
}

void SliceLayers::clearLabels() {
    labels_.reset();
    notInTable_.clear();
    seen_.clear();
    emit changed();
    emit legendChanged();
}

std::shared_ptr<const core::OctreeReader> SliceLayers::labelsReader() const {
    return labels_ ? labels_->reader : nullptr;
}

std::shared_ptr<const core::OctreeReader> SliceLayers::overlayReader() const {
    return overlay_ ? overlay_->reader : nullptr;
}

QString SliceLayers::overlayName() const { return overlay_ ? overlay_->name : QString(); }
QString SliceLayers::labelsName() const { return labels_ ? labels_->name : QString(); }

void SliceLayers::setOverlayMap(const core::ColorMap& map) {
    map_ = map;
    emit changed();
}
void SliceLayers::setOverlayWindow(const core::DisplayWindow& w) {
    window_ = w;
    emit changed();
}
void SliceLayers::setOverlayOpacity(double opacity) {
    overlayOpacity_ = opacity;
    emit changed();
}
void SliceLayers::setLabelOpacity(double opacity) {
    labelOpacity_ = opacity;
    emit changed();
}
void SliceLayers::setLabelFill(bool on) {
    fill_ = on;
    emit changed();
}
void SliceLayers::setLabelOutline(bool on) {
    outline_ = on;
    emit changed();
}
void SliceLayers::setLabelVisible(int label, bool visible) {
    table_.setVisible(label, visible);
    emit changed();
}

QImage SliceLayers::compose(const core::SliceImage& base, const core::VolumeGeometry& g, const core::SlicePlane& plane,
                            const core::DisplayWindow& w) {
    core::SliceImage overlayImage, labelImage;
    std::optional<core::SliceOverlay> overlay;
    std::optional<core::SliceLabels> labels;
    if (overlay_) {
        overlayImage = overlay_->sampler->sampleLike(plane, base);  // over a slab, the overlay's own slab
        overlay = core::SliceOverlay{&overlayImage, &overlay_->reader->geometry(), map_, window_, overlayOpacity_};
    }
    if (labels_) {
        labelImage = labels_->sampler->sample(plane);
        const auto present = core::SliceComposer::labelsIn(labelImage);
        const std::size_t known = seen_.size();
        seen_.insert(present.begin(), present.end());
        const auto added = table_.addMissing(present);
        if (!tablePath_.isEmpty()) notInTable_.insert(notInTable_.end(), added.begin(), added.end());
        if (seen_.size() != known || !added.empty()) emit legendChanged();
        labels = core::SliceLabels{&labelImage, &table_, labelOpacity_, fill_, outline_};
    }
    const auto rgb = core::SliceComposer::compose(base, g, w, overlay ? &*overlay : nullptr, labels ? &*labels : nullptr);
    QImage img(base.width, base.height, QImage::Format_RGB888);
    for (int y = 0; y < base.height; ++y)
        std::copy_n(rgb.data() + 3 * std::size_t(y) * std::size_t(base.width), 3 * std::size_t(base.width), img.scanLine(y));
    return img;
}

}  // namespace hvx::ui
