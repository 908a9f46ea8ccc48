// MainWindow: opening volumes — files, octrees, DICOM series, their time points — and what
// each brings back (its saved measurements, the editor's histogram and transfer function).
#include "ui/MainWindow.h"
#include "ui/CinePanel.h"
#include "ui/TimeSeriesLoader.h"



#include <QCryptographicHash>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QPointer>
#include <QSettings>
#include <QStatusBar>
#include <QTreeWidget>
#include <QTreeWidgetItemIterator>


#include <filesystem>

#include "core/base/AtomicFileWriter.h"
#include "core/base/Error.h"
#include "core/octree/OctreeBuilder.h"
#include "core/volume/VolumeChoice.h"
#include "core/volume/VoxelSourceFactory.h"
#include "core/streaming/OctreeSpace.h"
#include "core/reference/VolumeHistogram.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StudyDatabase.h"
#include "ui/CropControls.h"
#include "ui/JobManager.h"
#include "ui/MeasurementsPanel.h"
#include "ui/RenderControls.h"
#include "ui/SliceLayers.h"
#include "ui/SliceView.h"
#include "ui/SplitVoxelLink.h"
#include "ui/StudyBrowser.h"
#include "ui/TransferFunctionEditor.h"
#include "ui/VolumeView.h"

namespace hvx::ui {

bool MainWindow::openPath(const QString& path) {
    const QFileInfo info(path);
    if (!info.exists()) {
        showError(tr("%1 does not exist").arg(path));
        return false;
    }
    if (info.isFile() && path.endsWith(".hvo", Qt::CaseInsensitive)) return openOctree(path);
    if (info.isFile() && isVolumeFile(path)) return openVolumeFile(path);
    // DICOM: import, then open the first series of that import as the browser lists it (never
    // another patient's series that happened to be listed first).
    const int id = browser_->importPaths({path});
    QPointer<MainWindow> self(this);
    connect(browser_, &StudyBrowser::importedSeries, this, [self, id](int done, const QStringList& uids) {
        if (!self || done != id) return;
        auto* tree = self->browser_->tree();
        for (QTreeWidgetItemIterator it(tree); *it; ++it)
            if (uids.contains((*it)->data(0, Qt::UserRole + 1).toString())) {
                tree->setCurrentItem(*it);
                emit tree->itemActivated(*it, 0);
                break;
            }
    });
    return true;
}

bool MainWindow::openOctree(const QString& path, const QString& label, bool keepCamera) {
    try {
        std::shared_ptr<const core::OctreeReader> reader = core::OctreeReader::open(path.toStdString());
        reader_ = reader;
        lastNotice_.clear();  // a notice belongs to the file it was shown for
        const auto& g = reader->geometry();
        const auto space = core::OctreeSpace::of(g, reader->brickSize(), reader->levelCount());
        referenceLength_ = space.minSpacing;
        openLabel_ = label.isEmpty() ? QFileInfo(path).fileName() : label;
        setWindowTitle(tr("Holovox \u2014 %1").arg(openLabel_));
        const double pMin = g.valueMin * g.rescaleSlope + g.rescaleIntercept, pMax = g.valueMax * g.rescaleSlope + g.rescaleIntercept;
        controls_->setVolume(g.rescaleSlope, g.rescaleIntercept, std::min(pMin, pMax), std::max(pMin, pMax), g.hounsfield());
        tfEditor_->setVolume(g.valueMin, g.valueMax, g.rescaleSlope, g.rescaleIntercept, g.hounsfield(), {});
        view_->setVolume(reader, keepCamera);
        splitLink_->setVolume(reader, path, openLabel_);
        openPath_.clear();  // the new volume's crop box is not saved under the old one's key
        crop_->setVolume(g.dims, g.spacing, g.direction);
        view_->setRenderSettings(renderSettings());
        applyTransferFunction();
        layers_->setBase(reader, openLabel_);
        for (auto* s : slices_) s->setVolume(reader);
        openPath_ = QString::fromLatin1(
            QCryptographicHash::hash(QFileInfo(path).absoluteFilePath().toUtf8(), QCryptographicHash::Sha1).toHex());
        seriesUid_ = seriesOfOctree_.value(QFileInfo(path).absoluteFilePath());  // empty: a file of its own
        const QStringList saved = QSettings().value("windows/" + openPath_).toStringList();
        if (saved.size() == 3 && saved[1].toDouble() > 0)  // the window chosen last time for this volume
            for (auto* s : slices_) s->setWindow(saved[0].toDouble(), saved[1].toDouble(), saved[2]);
        restoreMeasurements(path);
        const QStringList crop = QSettings().value("crop/" + openPath_).toStringList();
        if (crop.size() == 6) {  // the crop box of last time, when it is a box of this volume
            core::CropBox b;
            bool ok = true;
            for (int a = 0; a < 3; ++a) {
                bool okLo = false, okHi = false;
                b.min[a] = crop[a].toDouble(&okLo);
                b.max[a] = crop[3 + a].toDouble(&okHi);
                ok = ok && okLo && okHi && b.min[a] >= 0.0 && b.max[a] <= 1.0 && b.max[a] > b.min[a];
            }
            if (ok) crop_->setBox(b);
        }
        // The histogram reads a few hundred bricks: in the background.
        QPointer<MainWindow> self(this);
        auto histogram = std::make_shared<core::VolumeHistogram>();
        jobs_->start(tr("Histogram of %1").arg(openLabel_),
                     [reader, histogram](core::JobContext&) {
                         *histogram = core::VolumeHistogram::compute(*reader);
                         return QString();
                     },
                     [self, reader, histogram](const QString&) {
                         if (self && self->reader_ == reader) {
                             const auto& geo = reader->geometry();
                             self->histogram_ = *histogram;
                             const auto spec = self->tfEditor_->spec();
                             self->tfEditor_->setVolume(geo.valueMin, geo.valueMax, geo.rescaleSlope, geo.rescaleIntercept, geo.hounsfield(), *histogram);
                             self->tfEditor_->setSpec(spec);  // keep what the user chose meanwhile
                             // Without a DICOM or CT window: the 1st-99th percentile, unless chosen.
                             const auto physical = [&](double v) { return v * geo.rescaleSlope + geo.rescaleIntercept; };
                             const auto w = core::DisplayWindow::initial(
                                 geo, std::make_pair(physical(histogram->percentile(0.01)), physical(histogram->percentile(0.99))));
                             for (auto* s : self->slices_) s->setAutomaticWindow(w);
                         }
                     });
        statusBar()->showMessage(tr("Opened %1").arg(openLabel_), 5000);
        setUpTimePoints(path);
        return true;
    } catch (const core::Error& e) {
        showError(QString::fromStdString(e.what()));
        return false;
    }
}

void MainWindow::setUpTimePoints(const QString& path) {
    delete timeLoader_;  // the previous series' builds are no longer wanted
    timeLoader_ = nullptr;
    timeReaders_.clear();
    timeNames_.clear();
    std::vector<dicom::VolumeRow> volumes;
    if (!seriesUid_.isEmpty()) {
        try {
            volumes = dicom::StudyDatabase(browser_->databasePath().toStdString()).volumesOfSeries(seriesUid_.toStdString());
        } catch (const core::Error&) {
            volumes.clear();
        }
    }
    const QString opened = QFileInfo(path).absoluteFilePath();
    int current = -1;
    for (std::size_t i = 0; i < volumes.size(); ++i) {
        timeNames_ << QStringLiteral("#%1 %2").arg(volumes[i].number).arg(QString::fromStdString(volumes[i].varying));
        if (!volumes[i].octreePath.empty() && QFileInfo(QString::fromStdString(volumes[i].octreePath)).absoluteFilePath() == opened)
            current = int(i);
    }
    if (volumes.size() < 2 || current < 0) {  // not one volume of a 4D series (or its preview)
        timeNames_.clear();
        cine_->clear();
        return;
    }
    // The series' label without its volume ("... #2 echo 2 (TE 20 ms)" as the browser names it).
    timeBaseLabel_ = openLabel_.endsWith(timeNames_[current]) ? openLabel_.chopped(timeNames_[current].size()).trimmed()
                                                               : openLabel_;
    splitLink_->setVolume(nullptr, {}, {});  // a 4D series is drawn from its own octrees
    timeReaders_.assign(volumes.size(), nullptr);
    timeReaders_[std::size_t(current)] = reader_;
    view_->setTimePoints(timeReaders_, current);
    cine_->setTimePoints(timeNames_, current);
    timeLoader_ = new TimeSeriesLoader(*jobs_, browser_->databasePath(), seriesUid_, volumes, current, reader_, this);
    connect(timeLoader_, &TimeSeriesLoader::ready, this,
            [this](int index, std::shared_ptr<const core::OctreeReader> reader) {
                timeReaders_[std::size_t(index)] = reader;
                view_->setTimePoint(index, std::move(reader));
                cine_->setReady(index, true);
            });
    connect(timeLoader_, &TimeSeriesLoader::refused, this,
            [this](int index, const QString& why) { cine_->setReady(index, false, why); });
    timeLoader_->start();
}

bool MainWindow::showTimePoint(int index) {
    if (index < 0 || index >= int(timeReaders_.size()) || !timeReaders_[std::size_t(index)]) return false;
    if (reader_ == timeReaders_[std::size_t(index)]) return true;
    if (!view_->showTimePoint(index)) return false;
    reader_ = timeReaders_[std::size_t(index)];
    for (auto* s : slices_) s->showTimePoint(reader_);
    openLabel_ = timeBaseLabel_ + " " + timeNames_[index];
    setWindowTitle(tr("Holovox \u2014 %1").arg(openLabel_));
    if (cine_->current() != index) cine_->setCurrent(index);
    return true;
}

void MainWindow::restoreMeasurements(const QString& path) {
    core::MeasurementSource source;
    source.volume = QFileInfo(path).absoluteFilePath().toStdString();
    source.spacingAssumed = reader_ && reader_->geometry().spacingAssumed;
    if (!seriesUid_.isEmpty()) {  // the patient, study and series UIDs from the study database
        try {
            dicom::StudyDatabase db(browser_->databasePath().toStdString());
            dicom::SeriesRow series;
            if (db.findSeries(seriesUid_.toStdString(), series)) {
                source.seriesUid = series.seriesUid;
                source.studyUid = series.studyUid;
                for (const auto& study : db.findStudies({}))
                    if (study.studyUid == series.studyUid) {
                        source.patientName = study.patientName;
                        source.patientId = study.patientId;
                    }
            }
        } catch (const std::exception&) {
            // without the database the exports carry the volume file only
        }
    }
    // Per series when the volume is one (its preview and its full octree share the list), else
    // per file.
    measurementsKey_ = seriesUid_.isEmpty()
                           ? openPath_
                           : QString::fromLatin1(QCryptographicHash::hash("series:" + seriesUid_.toUtf8(),
                                                                          QCryptographicHash::Sha1).toHex());
    core::MeasurementList list;
    const QString saved = QSettings().value("measurements/" + measurementsKey_).toString();
    if (!saved.isEmpty()) {
        try {
            list = core::MeasurementList::fromJson(saved.toStdString());
        } catch (const core::Error& e) {
            QSettings().remove("measurements/" + measurementsKey_);
            statusBar()->showMessage(tr("Saved measurements reset: %1").arg(QString::fromStdString(e.what())), 8000);
        }
    }
    measurements_->setVolume(source, list);
    for (auto* s : slices_) s->setMeasurements(measurements_->list().items());  // after the views' setVolume
    view_->setMeasurements(measurements_->list().items());
}

void MainWindow::openSeries(const QString& seriesUid, const QString& octreePath, const QString& label, int volume) {
    if (volume == 0) {  // a 4D series' own row: its first volume, so that cine has all of them
        std::vector<dicom::VolumeRow> volumes;
        try {
            volumes = dicom::StudyDatabase(browser_->databasePath().toStdString()).volumesOfSeries(seriesUid.toStdString());
        } catch (const core::Error&) {
            volumes.clear();
        }
        if (volumes.size() >= 2) {
            const auto& first = volumes.front();
            return openSeries(seriesUid, QString::fromStdString(first.octreePath),
                              QStringLiteral("%1 #%2 %3").arg(label).arg(first.number).arg(QString::fromStdString(first.varying)),
                              first.number);
        }
    }
    if (!octreePath.isEmpty()) {
        seriesOfOctree_[QFileInfo(octreePath).absoluteFilePath()] = seriesUid;
        openOctree(octreePath, label);
        return;
    }
    const std::string db = browser_->databasePath().toStdString(), uid = seriesUid.toStdString();
    QPointer<MainWindow> self(this);
    // First a quick preview (every 4th voxel), shown as soon as it exists; then the full octree,
    // which replaces it in place with the same camera. The full build starts once the preview
    // is on screen (or has failed), so the preview is always seen first and never raced.
    auto buildFull = [self, db, uid, label, volume](const QString& preview) {
        if (!self) return;
        self->jobs_->start(
            tr("Build octree: %1").arg(label),
            [db, uid, volume](core::JobContext& job) {
                dicom::StudyDatabase database(db);
                std::vector<std::string> warnings;
                return QString::fromStdString(dicom::SeriesOctree::build(database, uid, job, &warnings, {}, volume));
            },
            [self, label, preview, uid](const QString& path) {
                if (!self) return;
                self->browser_->refresh();
                self->seriesOfOctree_[QFileInfo(path).absoluteFilePath()] = QString::fromStdString(uid);
                self->openOctree(path, label, !preview.isEmpty());
                if (!preview.isEmpty()) QFile::remove(preview);
            });
    };
    const int previewJob = jobs_->start(
        tr("Preview: %1").arg(label),
        [db, uid, volume](core::JobContext& job) {
            dicom::StudyDatabase database(db);
            return QString::fromStdString(dicom::SeriesOctree::buildPreview(database, uid, job, 4, volume));
        },
        [self, label, buildFull, uid](const QString& path) {
            if (!self) return;
            self->seriesOfOctree_[QFileInfo(path).absoluteFilePath()] = QString::fromStdString(uid);
            buildFull(self->openOctree(path, label + tr(" (preview)")) ? path : QString());
        });
    // A preview that fails (or is cancelled) still leads to the full octree.
    auto once = std::make_shared<QMetaObject::Connection>();
    *once = connect(jobs_.get(), &JobManager::finished, this,
                    [once, previewJob, buildFull](int id, const QString& state, const QString&) {
                        if (id != previewJob) return;
                        QObject::disconnect(*once);
                        if (state != "done") buildFull(QString());
                    });
    statusBar()->showMessage(tr("Building the octree of %1 in the background; a preview comes first\u2026").arg(label), 5000);
}

void MainWindow::chooseImport() {
    const QString dir = QFileDialog::getExistingDirectory(this, tr("Import a folder (or the folder of a DICOMDIR)"));
    if (!dir.isEmpty()) browser_->importPaths({dir});
}

bool MainWindow::isVolumeFile(const QString& path) {
    static const char* suffixes[] = {".nii", ".nii.gz", ".nrrd", ".nhdr", ".mha", ".mhd", ".vtk", ".vti"};
    for (const char* s : suffixes)
        if (path.endsWith(QLatin1String(s), Qt::CaseInsensitive)) return true;
    return false;
}

bool MainWindow::openVolumeFile(const QString& path, int volume) {
    const QFileInfo info(path);
    const std::string file = info.absoluteFilePath().toStdString();
    int volumes = 1;
    try {
        volumes = int(core::VoxelSourceFactory::volumesIn(file));  // a 4-D NIfTI or NRRD asks which
    } catch (const core::Error& e) {
        showError(QString::fromStdString(e.what()));
        return false;
    }
    if (volume == 0 && volumes > 1) {
        bool ok = false;
        volume = QInputDialog::getInt(this, tr("Open a 4D volume"),
                                      tr("%1 holds %2 volumes. Open volume:").arg(info.fileName()).arg(volumes), 1, 1,
                                      volumes, 1, &ok);
        if (!ok) return false;
    }
    volume = std::max(volume, 1);
    const core::VolumeChoice choice{info.fileName().toStdString(), std::uint32_t(volumes), std::uint32_t(volume - 1)};
    if (const std::string refusal = choice.refusal(); !refusal.empty()) {
        showError(QString::fromStdString(refusal));
        return false;
    }
    const QString label = volumes > 1 ? tr("%1 \u2014 volume %2 of %3").arg(info.fileName()).arg(volume).arg(volumes)
                                      : info.fileName();
    // One octree per file version and volume, beside the study database's own.
    const QByteArray key = QCryptographicHash::hash(
        (info.absoluteFilePath() + "|" + QString::number(info.size()) + "|" +
         QString::number(info.lastModified().toMSecsSinceEpoch()) + "|" + QString::number(volume)).toUtf8(),
        QCryptographicHash::Sha1);
    const QString out = QFileInfo(browser_->databasePath()).absolutePath() + "/octrees/files/" +
                        QString::fromLatin1(key.toHex().left(20)) + ".hvo";
    // What the file leaves open or assumes (its source's warnings) is kept beside its octree and
    // said each time the octree opens, built now or found built.
    auto opened = [this, label](const QString& octree) {
        if (!openOctree(octree, label)) return false;
        QFile notes(octree + ".warnings");
        if (notes.open(QIODevice::ReadOnly)) {
            const QStringList lines = QString::fromUtf8(notes.readAll()).split('\n', Qt::SkipEmptyParts);
            if (!lines.isEmpty()) showNotice(lines.join("; "));
        }
        return true;
    };
    if (QFileInfo::exists(out)) return opened(out);
    QPointer<MainWindow> self(this);
    jobs_->start(
        tr("Build octree: %1").arg(label),
        [file, volume, out](core::JobContext& job) {
            auto source = core::VoxelSourceFactory::open(file, {}, std::uint32_t(volume - 1));
            std::filesystem::create_directories(std::filesystem::path(out.toStdString()).parent_path());
            const std::string notes = out.toStdString() + ".warnings";  // written before the octree it describes
            std::error_code ec;
            std::filesystem::remove(notes, ec);
            if (const auto warnings = source->warnings(); !warnings.empty()) {
                std::string text;
                for (const auto& w : warnings) text += w + "\n";
                core::AtomicFileWriter writer(notes);
                writer.append(text.data(), text.size());
                writer.commit();
            }
            try {
                core::OctreeBuilder(core::BuildOptions{}).build(*source, out.toStdString(), job);
            } catch (...) {  // no notes left beside an octree that was never written
                std::filesystem::remove(notes, ec);
                throw;
            }
            return out;
        },
        [self, opened](const QString& built) {
            if (self) opened(built);
        });
    statusBar()->showMessage(tr("Building the octree of %1 in the background\u2026").arg(label), 5000);
    return true;
}

void MainWindow::chooseOpen() {
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Open volume"), {},
        tr("Volumes (*.hvo *.nii *.nii.gz *.nrrd *.nhdr *.mha *.mhd *.vtk *.vti);;DICOM files (*)"));
    if (!path.isEmpty()) openPath(path);
}

}  // namespace hvx::ui
