#pragma once
#include <QObject>
#include <QString>

namespace hvx::ui {

class SliceLayers;
class VolumeView;

/// Lays the Layers dock's partner into the 3D view's ray march (VolumeView::setFusedVolume): the
/// label map when there is one (its table's colours, visibility and fill opacity), else the
/// overlay (its colour map over its window, at its opacity), each through its own working set.
/// Follows every change of the layers; off, the 3D view shows the open volume alone.
///
/// Threading: GUI thread only.
class FusionLink : public QObject {
    Q_OBJECT
public:
    FusionLink(SliceLayers& layers, VolumeView& view, QObject* parent = nullptr);
    /// Whether the partner is drawn in 3D (on by default).
    void setEnabled(bool on);
    bool enabled() const { return enabled_; }
    /// What the 3D view shows of the layers: "labels name", "overlay name", or empty.
    const QString& shown() const { return shown_; }

signals:
    /// Why the partner cannot be drawn in 3D (e.g. labels spanning more than the table holds).
    void failed(const QString& message);

private:
    void apply();

    SliceLayers& layers_;
    VolumeView& view_;
    bool enabled_ = true;
    QString shown_;
};

}  // namespace hvx::ui
