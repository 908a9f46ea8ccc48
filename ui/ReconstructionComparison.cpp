#include "ui/ReconstructionComparison.h"

#include <QComboBox>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QPixmap>

#include "core/base/Error.h"
#include "ui/SplitVoxelLink.h"
#include "ui/VolumeView.h"

namespace hvx::ui {

namespace {
constexpr int kSide = 320;
}

ReconstructionComparison::ReconstructionComparison(VolumeView& view, SplitVoxelLink& link,
                                                   std::shared_ptr<const core::OctreeReader> reader, QWidget* parent)
    : QDialog(parent), view_(view), link_(link), reader_(std::move(reader)), voxels_(new QComboBox(this)),
      status_(new QLabel(this)) {
    setWindowTitle(tr("Compare reconstructions"));
    setObjectName("reconstructionComparison");
    auto* top = new QHBoxLayout;
    top->addWidget(new QLabel(tr("One level, voxels of"), this));
    for (const int v : {2, 4, 8, 16}) voxels_->addItem(QString::number(v), v);
    voxels_->setCurrentIndex(1);
    voxels_->setToolTip(tr("The octree level compared: each voxel (or split-voxel cell) stands for this many voxels along an edge"));
    top->addWidget(voxels_);
    top->addStretch(1);
    auto* grid = new QGridLayout(this);
    grid->addLayout(top, 0, 0, 1, 3);
    for (int i = 0; i < 3; ++i) {
        images_[i] = new QLabel(this);
        images_[i]->setFixedSize(kSide, kSide);
        images_[i]->setStyleSheet("background: black");
        captions_[i] = new QLabel(this);
        captions_[i]->setAlignment(Qt::AlignCenter);
        grid->addWidget(images_[i], 1, i);
        grid->addWidget(captions_[i], 2, i);
    }
    status_->setWordWrap(true);
    grid->addWidget(status_, 3, 0, 1, 3);
    connect(voxels_, &QComboBox::currentIndexChanged, this, &ReconstructionComparison::render);
    connect(&link_, &SplitVoxelLink::ready, this, &ReconstructionComparison::render);
    if (link_.volume() == reader_ && !link_.splitReader()) {
        status_->setText(tr("Building the split-voxel octree (Jobs panel)\u2026"));
        link_.prepare();
    }
    render();
}

void ReconstructionComparison::setVoxels(int voxels) { voxels_->setCurrentIndex(voxels_->findData(voxels)); }

QString ReconstructionComparison::statusText() const { return status_->text(); }

QImage ReconstructionComparison::image(int i) const { return images_[i]->pixmap().toImage(); }

void ReconstructionComparison::render() {
    const int voxels = voxels_->currentData().toInt();
    int level = 0;
    while ((2 << level) <= voxels) ++level;  // voxels = 2^level
    const bool labels = reader_->geometry().isLabel;
    const bool linked = link_.volume() == reader_;  // not a 4D series, nor another volume opened since
    const auto split = linked ? link_.splitReader() : nullptr;
    try {
        if (level >= reader_->levelCount())
            throw core::Error(tr("The volume's octree has %1 levels: voxels of %2 are coarser than its root")
                                  .arg(reader_->levelCount()).arg(voxels).toStdString());
        const QSize size(kSide, kSide);
        images_[0]->setPixmap(QPixmap::fromImage(view_.renderLevel(reader_, level, false, size)));
        images_[1]->setPixmap(QPixmap::fromImage(view_.renderLevel(reader_, level, true, size)));
        captions_[0]->setText(labels ? tr("Trilinear (labels are never blended: nearest), level %1").arg(level)
                                     : tr("Trilinear, level %1").arg(level));
        captions_[1]->setText(tr("Nearest, level %1").arg(level));
        const int n = split ? int(split->header().split.n) : 2;
        int splitLevel = 0;
        while ((n << splitLevel) < voxels) ++splitLevel;
        if (!split) {
            images_[2]->clear();
            captions_[2]->setText(linked ? tr("Split-voxels: being built")
                                         : tr("Split-voxels: not for this volume (a 4D series, or no longer open)"));
        } else if ((n << splitLevel) != voxels || splitLevel >= split->levelCount()) {
            images_[2]->clear();
            captions_[2]->setText(tr("Split-voxels: no level of cells of %1 voxels").arg(voxels));
        } else {
            images_[2]->setPixmap(QPixmap::fromImage(view_.renderLevel(split, splitLevel, false, size)));
            captions_[2]->setText(tr("Split-voxels, cells of %1 voxels (level %2)").arg(voxels).arg(splitLevel));
            status_->setText(tr("DVR with the view's transfer function, camera and tools."));
        }
        ++rendered_;
        emit rendered();
    } catch (const core::Error& e) {
        status_->setText(QString::fromStdString(e.what()));
    }
}

}  // namespace hvx::ui
