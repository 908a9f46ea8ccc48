#include "ui/StudyBrowser.h"

#include <map>

#include <QColor>
#include <QComboBox>
#include <QFileInfo>

#include <memory>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QImage>
#include <QLabel>
#include <QMenu>
#include <QMessageBox>
#include <QLineEdit>
#include <QPixmap>
#include <QPushButton>
#include <QRegularExpressionValidator>
#include <QTreeWidget>
#include <QVBoxLayout>

#include <cmath>

#include "core/streaming/BrickCache.h"
#include "core/base/Error.h"
#include "core/octree/OctreeReader.h"
#include "core/reference/SliceSampler.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomInstance.h"
#include "dicom/DicomScanner.h"
#include "dicom/PixelDecoder.h"
#include "dicom/SeriesAssembler.h"
#include "dicom/PacsSettings.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StudyRemoval.h"
#include "dicom/StudyDatabase.h"
#include "ui/JobManager.h"

namespace hvx::ui {

namespace {
enum Role { SeriesUidRole = Qt::UserRole + 1, OctreeRole, LabelRole, VolumeRole, StudyUidRole };

// A 64-pixel axial thumbnail from the octree's coarse levels (a few bricks).
QIcon thumbnail(const std::string& octreePath) {
    try {
        const auto reader = core::OctreeReader::open(octreePath);
        core::BrickCache cache(32u << 20);
        const core::SliceSampler sampler(*reader, cache);
        const auto& g = reader->geometry();
        const glm::dvec3 centre = sampler.space().centre();
        const double extent = std::max(g.dims[0] * g.spacing.x, g.dims[1] * g.spacing.y);
        const auto img = sampler.sample(core::SlicePlane::standard(core::SlicePlane::Orientation::Axial, centre, extent / 64, 64, 64));
        QImage q(64, 64, QImage::Format_Grayscale8);
        const double lo = g.hounsfield() ? (-160 - g.rescaleIntercept) / g.rescaleSlope : g.valueMin;
        const double hi = g.hounsfield() ? (240 - g.rescaleIntercept) / g.rescaleSlope : g.valueMax;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const float v = img.values[std::size_t(y * 64 + x)];
                const double t = std::isnan(v) ? 0.0 : std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
                q.scanLine(y)[x] = std::uint8_t(t * 255);
            }
        return QIcon(QPixmap::fromImage(q));
    } catch (const std::exception&) {
        return {};
    }
}
// Without an octree: the middle image of the series, decoded from its DICOM file.
QIcon dicomThumbnail(const std::vector<std::string>& files) {
    if (files.empty()) return {};
    try {
        dicom::DicomInstance in;
        if (dicom::DicomHeaderReader::read(files[files.size() / 2], in) != dicom::DicomHeaderReader::Kind::Dicom ||
            !in.hasPixels() || in.samplesPerPixel != 1)
            return {};
        std::vector<std::int32_t> px;
        dicom::PixelDecoder().decode(in, in.frames / 2, px);
        if (px.size() < std::size_t(in.rows) * in.columns) return {};
        double lo = 1e300, hi = -1e300;
        for (auto v : px) lo = std::min(lo, double(v)), hi = std::max(hi, double(v));
        const auto* f = in.frameGeometry.empty() ? nullptr : &in.frame(in.frames / 2);
        if (in.modality == "CT" && f && (f->rescaleType.empty() || f->rescaleType == "HU")) {  // soft-tissue window
            lo = (-160 - f->rescaleIntercept) / f->rescaleSlope;
            hi = (240 - f->rescaleIntercept) / f->rescaleSlope;
        }
        const bool invert = in.photometric == "MONOCHROME1";
        QImage q(64, 64, QImage::Format_Grayscale8);
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const std::size_t r = std::size_t(y) * in.rows / 64, c = std::size_t(x) * in.columns / 64;
                double t = std::clamp((double(px[r * in.columns + c]) - lo) / std::max(1e-9, hi - lo), 0.0, 1.0);
                q.scanLine(y)[x] = std::uint8_t((invert ? 1.0 - t : t) * 255);
            }
        return QIcon(QPixmap::fromImage(q));
    } catch (const std::exception&) {
        return {};
    }
}
}  // namespace

StudyBrowser::StudyBrowser(JobManager& jobs, QString databasePath, QWidget* parent)
    : QWidget(parent), jobs_(jobs), dbPath_(std::move(databasePath)), text_(new QLineEdit(this)),
      from_(new QLineEdit(this)), to_(new QLineEdit(this)), modality_(new QComboBox(this)),
      tree_(new QTreeWidget(this)), count_(new QLabel(this)) {
    text_->setPlaceholderText(tr("Patient name or ID (* and ? allowed)"));
    text_->setClearButtonEnabled(true);
    const auto* date = new QRegularExpressionValidator(QRegularExpression("\\d{0,8}"), this);
    from_->setPlaceholderText(tr("from YYYYMMDD"));
    to_->setPlaceholderText(tr("to YYYYMMDD"));
    from_->setValidator(date);
    to_->setValidator(date);
    modality_->addItems({tr("Any"), "CT", "MR", "PT", "NM", "US", "XA", "CR", "DX", "MG", "RTDOSE"});
    modality_->setToolTip(tr("Studies with at least one series of this modality"));
    tree_->setHeaderLabels({tr("Patient / study / series"), tr("ID / date"), tr("Modality"), tr("Images"), tr("Notes")});
    // Columns fit their contents (a narrow dock scrolls rather than cutting names short).
    tree_->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
    tree_->header()->setStretchLastSection(true);
    tree_->setIconSize(QSize(40, 40));
    tree_->setAlternatingRowColors(true);
    tree_->setToolTip(tr("Double-click a series to open it"));
    auto* refreshButton = new QPushButton(tr("Search"), this);
    auto* filters = new QHBoxLayout;
    filters->addWidget(from_);
    filters->addWidget(to_);
    filters->addWidget(modality_);
    filters->addWidget(refreshButton);
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(4, 4, 4, 4);
    layout->addWidget(text_);
    layout->addLayout(filters);
    layout->addWidget(tree_, 1);
    layout->addWidget(count_);
    connect(refreshButton, &QPushButton::clicked, this, &StudyBrowser::refresh);
    connect(text_, &QLineEdit::returnPressed, this, &StudyBrowser::refresh);
    connect(from_, &QLineEdit::returnPressed, this, &StudyBrowser::refresh);  // Enter in a date searches too
    connect(to_, &QLineEdit::returnPressed, this, &StudyBrowser::refresh);
    connect(modality_, &QComboBox::activated, this, &StudyBrowser::refresh);
    connect(tree_, &QTreeWidget::itemActivated, this, &StudyBrowser::activated);
    tree_->setContextMenuPolicy(Qt::CustomContextMenu);
    connect(tree_, &QTreeWidget::customContextMenuRequested, this, [this](const QPoint& at) {
        QTreeWidgetItem* item = tree_->itemAt(at);
        if (item && !item->data(0, StudyUidRole).toString().isEmpty()) {
            QMenu menu(this);
            menu.addAction(tr("Remove study from this workstation\u2026"), this, [this, item] { confirmRemoval(item); });
            menu.exec(tree_->viewport()->mapToGlobal(at));
            return;
        }
        if (!item || item->data(0, SeriesUidRole).toString().isEmpty()) return;
        QMenu menu(this);
        menu.addAction(tr("Open"), this, [this, item] { activated(item); });
        menu.addAction(tr("Lay over the open volume (fusion)"), this, [this, item] { requestOverlay(item); });
        menu.exec(tree_->viewport()->mapToGlobal(at));
    });
    refresh();
}

void StudyBrowser::refresh() {
    // The row selected stays selected (a refresh after a build must not lose the open series).
    const QTreeWidgetItem* current = tree_->currentItem();
    const QString selectedUid = current ? current->data(0, SeriesUidRole).toString() : QString();
    const QVariant selectedVolume = current ? current->data(0, VolumeRole) : QVariant();
    tree_->clear();
    try {
        dicom::StudyDatabase db(dbPath_.toStdString());
        dicom::StudyQuery q;
        q.text = text_->text().toStdString();
        q.dateFrom = from_->text().toStdString();
        q.dateTo = to_->text().toStdString();
        q.modality = modality_->currentIndex() == 0 ? std::string() : modality_->currentText().toStdString();
        const auto studies = db.findStudies(q);
        QTreeWidgetItem* patient = nullptr;
        QString lastPatient;
        for (const auto& s : studies) {
            const QString key = QString::fromStdString(s.patientId + "\x1f" + s.patientName);
            if (!patient || key != lastPatient) {
                patient = new QTreeWidgetItem(tree_, {QString::fromStdString(s.patientName).replace('^', ' '),
                                                      QString::fromStdString(s.patientId), {}, {}});
                patient->setToolTip(0, tr("Born %1, sex %2").arg(QString::fromStdString(s.patientBirthDate),
                                                                  QString::fromStdString(s.patientSex)));
                lastPatient = key;
            }
            // The study's Images column counts its images (the series' own rows count theirs).
            const auto seriesRows = db.seriesOfStudy(s.studyUid);
            int images = 0;
            for (const auto& se : seriesRows) images += se.instanceCount;
            auto* study = new QTreeWidgetItem(patient, {QString::fromStdString(s.description.empty() ? "(no description)" : s.description),
                                                        QString::fromStdString(s.date), QString::fromStdString(s.modalities),
                                                        QString::number(images)});
            study->setToolTip(0, tr("Accession %1").arg(QString::fromStdString(s.accession)));
            study->setData(0, StudyUidRole, QString::fromStdString(s.studyUid));
            study->setData(0, LabelRole, QString::fromStdString(s.patientName).replace('^', ' ') + tr(", ID ") +
                                             QString::fromStdString(s.patientId));
            study->setToolTip(3, tr("%n image(s)", nullptr, images) + tr(" in %n series", nullptr, s.seriesCount));
            std::map<std::string, QTreeWidgetItem*> itemOfSeries;  // for the SEG and RTSTRUCT rows below
            for (const auto& se : seriesRows) {
                const QString label = QStringLiteral("%1 %2").arg(se.number).arg(QString::fromStdString(se.description));
                auto* item = new QTreeWidgetItem(study, {label, QString::fromStdString(se.bodyPart),
                                                         QString::fromStdString(se.modality), QString::number(se.instanceCount)});
                item->setData(0, SeriesUidRole, QString::fromStdString(se.seriesUid));
                item->setData(0, OctreeRole, QString::fromStdString(se.octreePath));
                item->setData(0, LabelRole, QString::fromStdString(s.patientName) + " \u2014 " + label);
                itemOfSeries[se.seriesUid] = item;
                // Thumbnails are made once per series (and again once its octree exists), not at
                // every refresh: they read bricks or decode a DICOM image on this thread.
                const bool octree = !se.octreePath.empty() && QFileInfo::exists(QString::fromStdString(se.octreePath));
                const QString thumbKey = QString::fromStdString(se.seriesUid + (octree ? "|" + se.octreePath : std::string()));
                auto cached = thumbnails_.find(thumbKey);
                if (cached == thumbnails_.end())
                    cached = thumbnails_.insert(thumbKey, octree ? thumbnail(se.octreePath)
                                                            : dicomThumbnail(db.filesOfSeries(se.seriesUid)));
                item->setIcon(0, *cached);
                QString tip = se.octreePath.empty() ? tr("No octree yet: opening builds it in the background")
                                                    : tr("Octree: %1").arg(QString::fromStdString(se.octreePath));
                if (se.modality == "SEG")
                    tip = tr("A segmentation: opening lays it over the open volume as labels (Layers dock)\n") + tip;
                if (se.modality == "RTSTRUCT")
                    tip = tr("A structure set: opening draws its contours onto the open volume's grid as labels "
                             "(Layers dock)");
                if (!se.warnings.empty()) {  // assumed spacing or orientation, gaps...: said in the row itself
                    QStringList lines;
                    for (const auto& w : se.warnings) lines << QString::fromStdString(w);
                    item->setText(4, tr("\u26A0 %1").arg(lines.first()) +
                                         (lines.size() > 1 ? tr(" (+%1 more)").arg(lines.size() - 1) : QString()));
                    item->setForeground(4, QColor(230, 170, 40));
                    tip += "\n\n" + lines.join("\n");
                }
                item->setToolTip(0, tip);
                item->setToolTip(4, tip);
                // A 4D series: one row per volume, with what varies (echo, b-value, time).
                for (const auto& v : db.volumesOfSeries(se.seriesUid)) {
                    const QString vlabel = QStringLiteral("#%1 %2").arg(v.number).arg(QString::fromStdString(v.varying));
                    auto* vitem = new QTreeWidgetItem(item, {vlabel, {}, QString::fromStdString(se.modality), {}});
                    vitem->setData(0, SeriesUidRole, QString::fromStdString(se.seriesUid));
                    vitem->setData(0, OctreeRole, QString::fromStdString(v.octreePath));
                    vitem->setData(0, LabelRole, QString::fromStdString(s.patientName) + " \u2014 " + label + " " + vlabel);
                    vitem->setData(0, VolumeRole, v.number);
                    vitem->setToolTip(0, tr("Volume %1 of the series: %2").arg(v.number).arg(QString::fromStdString(v.varying)));
                }
            }
            // A segmentation or structure set is listed under the image series it was drawn on
            // (when that series is in the study; otherwise in the study, saying so).
            for (const auto& se : seriesRows) {
                if (se.refersTo.empty()) continue;
                auto* item = itemOfSeries[se.seriesUid];
                const auto image = itemOfSeries.find(se.refersTo);
                if (image == itemOfSeries.end() || image->second == item) {
                    item->setToolTip(0, item->toolTip(0) + tr("\nIts image series (%1) is not in the database.")
                                                               .arg(QString::fromStdString(se.refersTo)));
                    continue;
                }
                study->removeChild(item);
                image->second->addChild(item);
            }
        }
        tree_->expandAll();
        if (!selectedUid.isEmpty())
            for (QTreeWidgetItemIterator it(tree_); *it; ++it)
                if ((*it)->data(0, SeriesUidRole).toString() == selectedUid && (*it)->data(0, VolumeRole) == selectedVolume) {
                    tree_->setCurrentItem(*it);
                    break;
                }
        count_->setText(tr("%n studies", nullptr, int(studies.size())));
    } catch (const core::Error& e) {
        count_->setText(QString::fromStdString(e.what()));
        emit failed(QString::fromStdString(e.what()));
    }
}

QTreeWidgetItem* StudyBrowser::seriesItem(const QString& seriesUid) const {
    for (QTreeWidgetItemIterator it(tree_); *it; ++it)
        if ((*it)->data(0, SeriesUidRole).toString() == seriesUid) return *it;
    return nullptr;
}

bool StudyBrowser::seriesOf(QTreeWidgetItem* item, QString& uid, QString& octree) const {
    uid = item ? item->data(0, SeriesUidRole).toString() : QString();
    if (uid.isEmpty()) return false;
    octree = item->data(0, OctreeRole).toString();
    if (!octree.isEmpty() && !QFileInfo::exists(octree)) octree.clear();
    return true;
}

void StudyBrowser::activated(QTreeWidgetItem* item) {
    QString uid, octree;
    if (!seriesOf(item, uid, octree)) return;
    // A segmentation or structure set is not a volume of its own: it is laid over the open
    // image as labels.
    if (item->text(2) == QLatin1String("SEG") || item->text(2) == QLatin1String("RTSTRUCT")) emit overlaySeries(uid, octree, item->data(0, LabelRole).toString(), 0);
    else emit openSeries(uid, octree, item->data(0, LabelRole).toString(), item->data(0, VolumeRole).toInt());
}

void StudyBrowser::requestOverlay(QTreeWidgetItem* item) {
    QString uid, octree;
    if (seriesOf(item, uid, octree))
        emit overlaySeries(uid, octree, item->data(0, LabelRole).toString(), item->data(0, VolumeRole).toInt());
}

void StudyBrowser::confirmRemoval(QTreeWidgetItem* study) {
    const QString uid = study->data(0, StudyUidRole).toString();
    QMessageBox ask(QMessageBox::Question, tr("Remove study"),
                    tr("Remove the study \u201c%1\u201d of %2 (%3 images) from this workstation?")
                        .arg(study->text(0), study->data(0, LabelRole).toString(), study->text(3)),
                    QMessageBox::Yes | QMessageBox::Cancel, this);
    ask.setObjectName("removeStudyQuestion");
    ask.setInformativeText(tr("It leaves the study database. The files Holovox received from a PACS and the octrees it "
                              "built are deleted (the PACS keeps its copy); files imported from your own folders stay "
                              "where they are. A volume of it that is open stays open."));
    ask.setDefaultButton(QMessageBox::Cancel);
    if (ask.exec() == QMessageBox::Yes) removeStudy(uid);
}

int StudyBrowser::removeStudy(const QString& studyUid) {
    const std::string db = dbPath_.toStdString(), uid = studyUid.toStdString();
    const std::string settings = pacsSettingsPath_.isEmpty() ? dicom::PacsSettings::defaultPath() : pacsSettingsPath_.toStdString();
    return jobs_.start(
        tr("Remove study"),
        [db, uid, settings](core::JobContext&) {
            const std::string storage = dicom::PacsSettings::load(settings).local.storageDir;
            dicom::StudyDatabase database(db);
            const auto r = dicom::StudyRemoval::remove(database, uid, storage, dicom::SeriesOctree::folderFor(db));
            QString summary = QObject::tr("study of %1 removed: %2 image(s) forgotten, %3 received file(s) and %4 octree(s) "
                                          "deleted, %5 imported file(s) kept")
                                  .arg(QString::fromStdString(r.patient))
                                  .arg(r.forgotten).arg(r.deleted).arg(r.octrees).arg(r.kept);
            if (r.shared)
                summary += QObject::tr("; %1 received file(s) kept, which another study database indexes (%2)")
                               .arg(r.shared)
                               .arg(QString::fromStdString(r.sharers.front()));
            if (!r.failed.empty())
                throw core::Error(summary.toStdString() + "; could not delete " + r.failed.front() +
                                  (r.failed.size() > 1 ? " and " + std::to_string(r.failed.size() - 1) + " more" : "") +
                                  (r.reindexed ? "; " + std::to_string(r.reindexed) +
                                                     " of them indexed again: the study stays listed with them (remove "
                                                     "it again once they can be deleted)"
                                               : std::string()));
            return summary;
        },
        [this](const QString& summary) {
            refresh();
            emit studyRemoved(summary);
        });
}

int StudyBrowser::importPaths(const QStringList& paths) {
    std::vector<std::string> list;
    for (const auto& p : paths) list.push_back(p.toStdString());
    const std::string db = dbPath_.toStdString();
    // Written by the job's thread before it ends, read on this thread once it has.
    auto found = std::make_shared<QStringList>();
    auto id = std::make_shared<int>(0);
    *id = jobs_.start(
        tr("Import %1").arg(paths.size() == 1 ? QFileInfo(paths.first()).fileName() : tr("%n items", nullptr, int(paths.size()))),
        [list, db, found](core::JobContext& job) {
            const auto scan = dicom::DicomScanner::scan(list, job);
            dicom::StudyDatabase database(db);
            const auto stats = database.addInstances(scan.instances);
            std::vector<std::string> notes;  // a 4D series' volumes, for the rows below it
            const auto accepted = stats.accepted(scan.instances);
            dicom::SeriesOctree::recordVolumes(database, dicom::SeriesAssembler::assemble(accepted, notes), accepted);
            if (scan.instances.empty())
                throw core::Error(scan.broken ? "no readable DICOM found: " + std::to_string(scan.broken) + " broken files"
                                              : std::string("no DICOM files found there"));
            for (const auto& i : stats.accepted(scan.instances))
                if (!found->contains(QString::fromStdString(i.seriesInstanceUid)))
                    found->append(QString::fromStdString(i.seriesInstanceUid));
            QString summary = QObject::tr("%1 DICOM files (%2 new), %3 not DICOM, %4 broken")
                                  .arg(scan.instances.size()).arg(stats.added).arg(scan.notDicom).arg(scan.broken);
            if (scan.setAside)
                summary += QObject::tr("; %1 file(s) a receive set aside in its storage folder not imported "
                                       "(.incoming: still being received; .conflicts: refused on receipt)")
                               .arg(scan.setAside);
            for (const auto& c : stats.conflicts) summary += "; " + QString::fromStdString(c);
            return summary;
        },
        [this, found, id](const QString& summary) {
            refresh();
            emit imported(summary);
            emit importedSeries(*id, *found);
        });
    return *id;
}

}  // namespace hvx::ui
