#include "ui/SplitVoxelLink.h"

#include <QComboBox>
#include <QCryptographicHash>
#include <QDateTime>
#include <QDir>
#include <QFileInfo>
#include <QSettings>
#include <QStandardPaths>

#include "core/octree/OctreeVoxelSource.h"
#include "core/octree/SplitVoxelOctreeBuilder.h"
#include "ui/JobManager.h"
#include "ui/RenderControls.h"
#include "ui/VolumeView.h"

namespace hvx::ui {

namespace {
using Reconstruction = RenderControls::Reconstruction;
const char* const kNames[] = {"trilinear", "nearest", "split-voxels"};

Reconstruction parse(const QString& name, Reconstruction fallback) {
    for (int i = 0; i < 3; ++i)
        if (name == QLatin1String(kNames[i])) return Reconstruction(i);
    return fallback;
}
}  // namespace

SplitVoxelLink::SplitVoxelLink(RenderControls& controls, VolumeView& view, JobManager& jobs, QObject* parent)
    : QObject(parent), controls_(controls), view_(view), jobs_(jobs) {
    connect(&controls_, &RenderControls::changed, this, &SplitVoxelLink::apply);
    connect(&jobs_, &JobManager::finished, this, [this](int id, const QString& state, const QString&) {
        if (id != job_) return;
        job_ = -1;
        if (state == "done" || !reader_) return;
        // Not built (too large, a full disk, cancelled): the volume's own octree, as it would be by default.
        const bool labels = reader_->geometry().isLabel;
        controls_.setReconstruction(labels ? Reconstruction::Nearest : Reconstruction::Trilinear, labels);
        emit controls_.changed();
    });
}

QString SplitVoxelLink::cachePath(const QString& path) {
    const QFileInfo info(path);
    const QString identity = info.absoluteFilePath() + '\n' + QString::number(info.size()) + '\n' +
                             QString::number(info.lastModified().toMSecsSinceEpoch());
    const QString name = QString::fromLatin1(QCryptographicHash::hash(identity.toUtf8(), QCryptographicHash::Sha1).toHex());
    return QStandardPaths::writableLocation(QStandardPaths::CacheLocation) + "/split-voxels/" + name + ".hvo";
}

void SplitVoxelLink::setVolume(std::shared_ptr<const core::OctreeReader> reader, const QString& path, const QString& label) {
    reader_ = std::move(reader);
    split_.reset();
    applied_.reset();
    job_ = -1;  // a build still running for the previous volume goes on (its file is kept for next time)
    path_ = path;
    label_ = label;
    key_ = QString::fromLatin1(
        QCryptographicHash::hash(QFileInfo(path).absoluteFilePath().toUtf8(), QCryptographicHash::Sha1).toHex());
    view_.setSplitVolume(nullptr);
    auto* box = controls_.reconstructionBox();
    box->setEnabled(reader_ != nullptr);
    if (!reader_) return;
    const bool labels = reader_->geometry().isLabel;
    const Reconstruction fallback =
        labels ? Reconstruction::SplitVoxels : parse(QSettings().value("reconstruction/default").toString(), Reconstruction::Trilinear);
    controls_.setReconstruction(parse(QSettings().value("reconstruction/" + key_).toString(), fallback), labels);
    apply();
}

void SplitVoxelLink::apply() {
    if (!reader_) return;
    const Reconstruction r = controls_.reconstruction();
    if (applied_ && *applied_ == int(r)) return;  // another control of the dock changed
    applied_ = int(r);
    QSettings().setValue("reconstruction/" + key_, QLatin1String(kNames[int(r)]));
    if (r != Reconstruction::SplitVoxels) {
        view_.setSplitVolume(nullptr);
        return;
    }
    if (split_) view_.setSplitVolume(split_);
    else prepare();
}

void SplitVoxelLink::prepare() {
    if (!reader_ || split_) return;
    const QString cached = cachePath(path_);
    if (QFileInfo::exists(cached)) {
        try {
            split_ = core::OctreeReader::open(cached.toStdString(), true);
            if (controls_.reconstruction() == Reconstruction::SplitVoxels) view_.setSplitVolume(split_);
            emit ready();
            return;
        } catch (const core::Error&) {
            QFile::remove(cached);  // damaged or from another version: built again
        }
    }
    build();
}

void SplitVoxelLink::build() {
    if (job_ >= 0) return;
    const auto reader = reader_;
    const QString path = cachePath(path_);
    QDir().mkpath(QFileInfo(path).absolutePath());
    job_ = jobs_.start(
        tr("Split-voxels of %1").arg(label_),
        [reader, path](core::JobContext& job) {
            core::OctreeVoxelSource source(reader);
            core::BuildOptions b;
            b.brickSize = reader->brickSize();
            core::SplitVoxelOptions o;
            o.labels = reader->geometry().isLabel;
            const auto report = core::SplitVoxelOctreeBuilder(b, o).build(source, path.toStdString(), job);
            return tr("split-voxels built in %1 s").arg(report.seconds, 0, 'f', 1);
        },
        [this, reader, path](const QString&) {
            if (reader != reader_) return;  // another volume opened meanwhile: kept for next time
            try {
                split_ = core::OctreeReader::open(path.toStdString(), true);
            } catch (const core::Error&) {
                return;  // removed meanwhile: built again when chosen again
            }
            if (controls_.reconstruction() == Reconstruction::SplitVoxels) view_.setSplitVolume(split_);
            emit ready();
        });
}

}  // namespace hvx::ui
