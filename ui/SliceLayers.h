#pragma once
#include <QImage>
#include <QObject>
#include <QString>

#include <memory>
#include <optional>
#include <set>

#include "core/appearance/ColorMap.h"
#include "core/appearance/LabelTable.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/SliceSampler.h"
#include "core/streaming/BrickCache.h"
#include "core/volume/DisplayWindow.h"

namespace hvx::ui {

/// The volumes laid over the open one in the slice views: one overlay (a second volume in
/// colour: PET over CT, a parameter map over anatomy) and one label map, each sampled on the
/// slice's own plane at the same patient points (their own grids, their own levels), and their
/// settings. A partner in another frame of reference, or without a known orientation, is
/// refused unless forced (core::FramePairing); when the open volume changes, a partner that no
/// longer pairs is dropped with a note.
///
/// Threading: GUI thread only.
class SliceLayers : public QObject {
    Q_OBJECT
public:
    explicit SliceLayers(QObject* parent = nullptr);
    ~SliceLayers() override;

    /// The open volume (null: none), named in messages; re-checks the partners.
    void setBase(std::shared_ptr<const core::OctreeReader> base, const QString& name);
    /// Lays the octree at `path` over the open volume in colour. Returns an empty string, or
    /// the sentence why not (then nothing changes). `force` lays over a refused pairing.
    QString setOverlay(const QString& path, const QString& name, bool force = false);
    /// Lays a label map (an octree built with --labels) over the open volume; as setOverlay.
    QString setLabels(const QString& path, const QString& name, bool force = false);
    /// The label map's colours from a table file (empty: generated colours). Returns an empty
    /// string or why the table was refused (the colours stay as they were).
    QString setLabelTable(const QString& path);
    void clearOverlay();
    void clearLabels();

    /// The open volume, the label map's and the overlay's readers (null when none), for work on
    /// other threads and the 3D view.
    std::shared_ptr<const core::OctreeReader> base() const { return base_; }
    std::shared_ptr<const core::OctreeReader> labelsReader() const;
    std::shared_ptr<const core::OctreeReader> overlayReader() const;
    bool hasOverlay() const { return overlay_ != nullptr; }
    bool hasLabels() const { return labels_ != nullptr; }
    QString overlayName() const;
    QString labelsName() const;
    /// The last pairing note or refusal ("the frame of reference of ... is not known ...").
    const QString& note() const { return note_; }

    void setOverlayMap(const core::ColorMap& map);
    void setOverlayWindow(const core::DisplayWindow& w);
    void setOverlayOpacity(double opacity);
    const core::ColorMap& overlayMap() const { return map_; }
    const core::DisplayWindow& overlayWindow() const { return window_; }
    double overlayOpacity() const { return overlayOpacity_; }

    void setLabelOpacity(double opacity);
    void setLabelFill(bool on);
    void setLabelOutline(bool on);
    void setLabelVisible(int label, bool visible);
    double labelOpacity() const { return labelOpacity_; }
    bool labelFill() const { return fill_; }
    bool labelOutline() const { return outline_; }
    const core::LabelTable& labelTable() const { return table_; }
    /// The labels the slices have shown since the label map was laid over (the legend lists
    /// these, and every label of a table of at most 64).
    const std::set<int>& labelsSeen() const { return seen_; }
    /// Labels a slice showed that the chosen table lacks (given generated colours).
    const std::vector<int>& labelsNotInTable() const { return notInTable_; }

    /// The slice as the reader sees it: `base` (sampled on `plane`, of geometry `g`) in grey through `w`, the
    /// layers over it (RGB888).
    QImage compose(const core::SliceImage& base, const core::VolumeGeometry& g, const core::SlicePlane& plane,
                   const core::DisplayWindow& w);

signals:
    /// A layer or a setting changed: the slices should be drawn again.
    void changed();
    /// The labels known changed (a table, or labels seen for the first time).
    void legendChanged();

private:
    struct Layer;
    std::unique_ptr<Layer> open(const QString& path, const QString& name, bool force, QString& error) const;

    std::shared_ptr<const core::OctreeReader> base_;
    QString baseName_;
    std::unique_ptr<Layer> overlay_, labels_;
    core::ColorMap map_ = core::ColorMap::named("hot");
    core::DisplayWindow window_;
    double overlayOpacity_ = 0.5;
    core::LabelTable table_;
    QString tablePath_;
    QString sidecarTable_;  // tablePath_ when it is the label map's own table
    std::vector<int> notInTable_;
    std::set<int> seen_;
    double labelOpacity_ = 0.5;
    bool fill_ = true, outline_ = true;
    QString note_;
};

}  // namespace hvx::ui
