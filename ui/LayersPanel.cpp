#include "ui/LayersPanel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPixmap>
#include <QPushButton>
#include <QSlider>
#include <QTreeWidget>
#include <QVBoxLayout>

#include <QPointer>

#include <algorithm>
#include <cmath>

#include "core/base/AtomicFileWriter.h"
#include "core/base/Error.h"
#include "core/octree/OctreeReader.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StudyDatabase.h"
#include "ui/JobManager.h"
#include "ui/SliceLayers.h"

namespace hvx::ui {

namespace {
QSlider* percentSlider(int value) {
    auto* s = new QSlider(Qt::Horizontal);
    s->setRange(0, 100);
    s->setValue(value);
    return s;
}
}  // namespace

LayersPanel::LayersPanel(SliceLayers& layers, QWidget* parent) : QWidget(parent), layers_(layers) {
    auto* top = new QVBoxLayout(this);

    auto* overlayBox = new QGroupBox(tr("Overlay (fusion)"));
    auto* of = new QFormLayout(overlayBox);
    overlayName_ = new QLabel;
    overlayName_->setWordWrap(true);
    auto* overlayButtons = new QHBoxLayout;
    auto* overlayButton = new QPushButton(tr("Overlay\u2026"));
    overlayButton->setToolTip(tr("Lay a second volume (an .hvo octree in the same frame of reference) over the open one"));
    removeOverlay_ = new QPushButton(tr("Remove"));
    overlayButtons->addWidget(overlayButton);
    overlayButtons->addWidget(removeOverlay_);
    of->addRow(overlayName_);
    of->addRow(overlayButtons);
    map_ = new QComboBox;
    for (const auto& n : core::ColorMap::builtinNames()) map_->addItem(QString::fromStdString(n));
    map_->addItem(tr("From a file\u2026"));
    map_->setCurrentText(QStringLiteral("hot"));
    of->addRow(tr("Colour map"), map_);
    overlayWidth_ = new QDoubleSpinBox;
    overlayLevel_ = new QDoubleSpinBox;
    for (auto* s : {overlayWidth_, overlayLevel_}) {
        s->setRange(-1e9, 1e9);
        s->setDecimals(2);
        s->setKeyboardTracking(false);
    }
    overlayWidth_->setMinimum(1e-6);
    of->addRow(tr("Window W"), overlayWidth_);
    of->addRow(tr("Level L"), overlayLevel_);
    overlayOpacity_ = percentSlider(50);
    of->addRow(tr("Opacity"), overlayOpacity_);
    top->addWidget(overlayBox);

    auto* labelBox = new QGroupBox(tr("Labels"));
    auto* lf = new QFormLayout(labelBox);
    labelsName_ = new QLabel;
    labelsName_->setWordWrap(true);
    auto* labelButtons = new QHBoxLayout;
    auto* labelsButton = new QPushButton(tr("Labels\u2026"));
    labelsButton->setToolTip(tr("Lay a label map (an .hvo octree built with --labels) over the open volume"));
    auto* tableButton = new QPushButton(tr("Colour table\u2026"));
    tableButton->setToolTip(tr("ITK-SNAP label descriptions, FreeSurfer LUT, 3D Slicer .ctbl or mricron .lut"));
    removeLabels_ = new QPushButton(tr("Remove"));
    labelButtons->addWidget(labelsButton);
    labelButtons->addWidget(tableButton);
    labelButtons->addWidget(removeLabels_);
    lf->addRow(labelsName_);
    lf->addRow(labelButtons);
    labelOpacity_ = percentSlider(50);
    lf->addRow(tr("Fill opacity"), labelOpacity_);
    fill_ = new QCheckBox(tr("Fill"));
    outline_ = new QCheckBox(tr("Outline"));
    fill_->setChecked(true);
    outline_->setChecked(true);
    auto* drawRow = new QHBoxLayout;
    drawRow->addWidget(fill_);
    drawRow->addWidget(outline_);
    lf->addRow(drawRow);
    legend_ = new QTreeWidget;
    legend_->setObjectName(QStringLiteral("labelLegend"));
    legend_->setHeaderLabels({tr("Label"), tr("Name"), tr("Volume (mL)"), tr("Mean \u00b1 SD")});
    legend_->setRootIsDecorated(false);
    legend_->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
    legend_->setMinimumHeight(90);
    lf->addRow(legend_);
    statisticsButton_ = new QPushButton(tr("Statistics"));
    statisticsButton_->setToolTip(tr("Each label's volume and the open volume's mean and SD over it, from the finest level"));
    exportButton_ = new QPushButton(tr("Export CSV\u2026"));
    auto* statsRow = new QHBoxLayout;
    statsRow->addWidget(statisticsButton_);
    statsRow->addWidget(exportButton_);
    lf->addRow(statsRow);
    top->addWidget(labelBox);

    force_ = new QCheckBox(tr("Lay over even in another frame of reference"));
    force_->setToolTip(tr("Only for volumes known to be registered: their patient coordinates are taken as the same"));
    top->addWidget(force_);
    show3D_ = new QCheckBox(tr("Show in the 3D view"));
    show3D_->setChecked(true);
    show3D_->setToolTip(tr("The label map (or else the overlay) is marched with the open volume in the 3D view, "
                           "each from its own bricks; drawn in DVR without the illustrative tools"));
    top->addWidget(show3D_);
    connect(show3D_, &QCheckBox::toggled, this, &LayersPanel::show3DToggled);
    message_ = new QLabel;
    message_->setWordWrap(true);
    message_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    top->addWidget(message_);
    top->addStretch(1);

    connect(overlayButton, &QPushButton::clicked, this, [this] {
        const QString path = QFileDialog::getOpenFileName(this, tr("Overlay"), {}, tr("Holovox octrees (*.hvo)"));
        if (!path.isEmpty()) chooseOverlay(path);
    });
    connect(labelsButton, &QPushButton::clicked, this, [this] {
        const QString path = QFileDialog::getOpenFileName(this, tr("Label map"), {}, tr("Holovox octrees (*.hvo)"));
        if (!path.isEmpty()) chooseLabels(path);
    });
    connect(tableButton, &QPushButton::clicked, this, [this] {
        const QString path = QFileDialog::getOpenFileName(this, tr("Colour table"), {},
                                                          tr("Colour tables (*.txt *.ctbl *.lut *.label);;All files (*)"));
        if (!path.isEmpty()) chooseLabelTable(path);
    });
    connect(statisticsButton_, &QPushButton::clicked, this, &LayersPanel::computeStatistics);
    connect(exportButton_, &QPushButton::clicked, this, [this] {
        const QString path = QFileDialog::getSaveFileName(this, tr("Label statistics"), tr("label-statistics.csv"),
                                                          tr("CSV (*.csv)"));
        if (!path.isEmpty()) exportStatistics(path);
    });
    connect(removeOverlay_, &QPushButton::clicked, &layers_, &SliceLayers::clearOverlay);
    connect(removeLabels_, &QPushButton::clicked, &layers_, &SliceLayers::clearLabels);
    connect(map_, &QComboBox::activated, this, [this](int index) {
        if (index < int(core::ColorMap::builtinNames().size())) {
            layers_.setOverlayMap(core::ColorMap::named(map_->itemText(index).toStdString()));
            return;
        }
        const QString path = QFileDialog::getOpenFileName(this, tr("Colour map"), {}, tr("Colour maps (*.lut *.ctbl *.txt)"));
        try {
            if (!path.isEmpty()) layers_.setOverlayMap(core::ColorMap::load(path.toStdString()));
        } catch (const core::Error& e) {
            show(QString::fromStdString(e.what()), true);
        }
        refresh();
    });
    connect(overlayWidth_, &QDoubleSpinBox::valueChanged, this, &LayersPanel::applyOverlayWindow);
    connect(overlayLevel_, &QDoubleSpinBox::valueChanged, this, &LayersPanel::applyOverlayWindow);
    connect(overlayOpacity_, &QSlider::valueChanged, this, [this](int v) { layers_.setOverlayOpacity(v / 100.0); });
    connect(labelOpacity_, &QSlider::valueChanged, this, [this](int v) { layers_.setLabelOpacity(v / 100.0); });
    connect(fill_, &QCheckBox::toggled, &layers_, &SliceLayers::setLabelFill);
    connect(outline_, &QCheckBox::toggled, &layers_, &SliceLayers::setLabelOutline);
    connect(legend_, &QTreeWidget::itemChanged, this, [this](QTreeWidgetItem* item) {
        if (!updating_) layers_.setLabelVisible(item->data(0, Qt::UserRole).toInt(), item->checkState(0) == Qt::Checked);
    });
    connect(&layers_, &SliceLayers::changed, this, &LayersPanel::refresh);
    connect(&layers_, &SliceLayers::legendChanged, this, &LayersPanel::refreshLegend);
    refresh();
}

void LayersPanel::show(const QString& text, bool error) {
    message_->setText(text);
    message_->setStyleSheet(error ? QStringLiteral("color: #e05050;") : QString());
}

QString LayersPanel::message() const { return message_->text(); }

void LayersPanel::setJobs(JobManager* jobs, const QString& databasePath) {
    jobs_ = jobs;
    databasePath_ = databasePath;
}

void LayersPanel::overlaySeries(const QString& seriesUid, const QString& octreePath, const QString& label, int volume) {
    if (!octreePath.isEmpty() || !jobs_) {
        layOver(octreePath, label);
        return;
    }
    if (!layers_.base()) {
        show(tr("Open a volume first: %1 is laid over the open volume.").arg(label), true);
        return;
    }
    show(tr("Building the octree of %1 to lay it over the open volume\u2026").arg(label), false);
    const std::string db = databasePath_.toStdString(), uid = seriesUid.toStdString();
    const core::VolumeGeometry grid = layers_.base()->geometry();  // a structure set's contours are drawn onto it
    QPointer<LayersPanel> self(this);
    auto warnings = std::make_shared<std::vector<std::string>>();  // said once the layer is shown
    const int id = jobs_->start(
        tr("Build octree: %1").arg(label),
        [db, uid, volume, grid, warnings](core::JobContext& job) {
            dicom::StudyDatabase database(db);
            if (dicom::SeriesOctree::isStructureSet(database, uid))
                return QString::fromStdString(dicom::SeriesOctree::buildStructureSet(database, uid, grid, job, warnings.get()));
            return QString::fromStdString(dicom::SeriesOctree::build(database, uid, job, warnings.get(), {}, volume));
        },
        [self, label, warnings](const QString& path) {
            if (!self || !self->layOver(path, label) || warnings->empty()) return;
            QStringList lines;
            for (const auto& w : *warnings) lines << QString::fromStdString(w);
            self->show(self->message() + "\n" + lines.join("\n"), false);
        });
    // A build that fails (a structure set of another frame, contours off the grid) says why here too.
    auto once = std::make_shared<QMetaObject::Connection>();
    *once = connect(jobs_, &JobManager::finished, this, [this, once, id](int done, const QString& state, const QString& message) {
        if (done != id) return;
        QObject::disconnect(*once);
        if (state == "failed") show(message, true);
    });
}

bool LayersPanel::layOver(const QString& octreePath, const QString& label) {
    bool labels = false;
    try {
        labels = core::OctreeReader::open(octreePath.toStdString())->geometry().isLabel;
    } catch (const core::Error& e) {
        show(QString::fromStdString(e.what()), true);
        return false;
    }
    return labels ? chooseLabels(octreePath, label) : chooseOverlay(octreePath, label);
}

int LayersPanel::computeStatistics() {
    const auto image = layers_.base();
    const auto labels = layers_.labelsReader();
    if (!image || !labels || !jobs_) return -1;
    auto result = std::make_shared<core::LabelStatistics>();
    QPointer<LayersPanel> self(this);
    return jobs_->start(
        tr("Label statistics: %1").arg(layers_.labelsName()),
        [image, labels, result](core::JobContext& job) {
            *result = core::LabelStatistics::compute(*image, *labels, job);
            return QString::number(result->rows.size()) + " labels";
        },
        [self, result, image, labels](const QString&) {
            if (!self || self->layers_.labelsReader() != labels || self->layers_.base() != image) return;  // changed since
            self->statistics_ = result;
            self->statisticsImage_ = image;
            self->statisticsLabels_ = labels;
            self->show(QString::fromStdString(result->note), false);
            self->refreshLegend();
            self->refresh();
        });
}

bool LayersPanel::exportStatistics(const QString& path) {
    if (statistics_->rows.empty()) {
        show(tr("No statistics yet: press Statistics first."), true);
        return false;
    }
    try {
        const std::string csv = statistics_->csv(&layers_.labelTable());
        core::AtomicFileWriter w(path.toStdString());
        w.append(csv.data(), csv.size());
        w.commit();
    } catch (const core::Error& e) {
        show(QString::fromStdString(e.what()), true);
        return false;
    }
    show(tr("Saved %1.").arg(path), false);
    return true;
}

bool LayersPanel::chooseOverlay(const QString& path, const QString& name) {
    const QString error = layers_.setOverlay(path, name, force_->isChecked());
    show(error.isEmpty() ? layers_.note() : error, !error.isEmpty());
    return error.isEmpty();
}

bool LayersPanel::chooseLabels(const QString& path, const QString& name) {
    const QString error = layers_.setLabels(path, name, force_->isChecked());
    show(error.isEmpty() ? layers_.note() : error, !error.isEmpty());
    return error.isEmpty();
}

bool LayersPanel::chooseLabelTable(const QString& path) {
    const QString error = layers_.setLabelTable(path);
    show(error.isEmpty() ? tr("Colours from %1 (%2).").arg(path, QString::fromStdString(layers_.labelTable().format()))
                         : error,
         !error.isEmpty());
    return error.isEmpty();
}

void LayersPanel::applyOverlayWindow() {
    if (!updating_ && overlayWidth_->value() > 0)
        layers_.setOverlayWindow({"", overlayLevel_->value(), overlayWidth_->value()});
}

void LayersPanel::refresh() {
    updating_ = true;
    overlayName_->setText(layers_.hasOverlay() ? layers_.overlayName() : tr("No overlay."));
    labelsName_->setText(layers_.hasLabels() ? layers_.labelsName() : tr("No label map."));
    for (QWidget* w : std::initializer_list<QWidget*>{map_, overlayWidth_, overlayLevel_, overlayOpacity_, removeOverlay_})
        w->setEnabled(layers_.hasOverlay());
    for (QWidget* w : std::initializer_list<QWidget*>{labelOpacity_, fill_, outline_, legend_, removeLabels_, statisticsButton_})
        w->setEnabled(layers_.hasLabels());
    exportButton_->setEnabled(layers_.hasLabels() && !statistics_->rows.empty());
    // Three significant digits of the width, however small the overlay's values (an ADC map in
    // mm²/s): two decimals had turned a width of 0.0025 into 0.
    const double width = layers_.overlayWindow().width;
    const int decimals = std::clamp(3 - int(std::floor(std::log10(width > 0 ? width : 1.0))), 2, 12);
    for (auto* s : {overlayWidth_, overlayLevel_}) {
        s->setDecimals(decimals);
        s->setSingleStep(std::pow(10.0, 1 - decimals));
    }
    overlayWidth_->setMinimum(std::pow(10.0, -decimals));
    overlayWidth_->setValue(width);
    overlayLevel_->setValue(layers_.overlayWindow().centre);
    overlayOpacity_->setValue(int(std::lround(layers_.overlayOpacity() * 100)));
    labelOpacity_->setValue(int(std::lround(layers_.labelOpacity() * 100)));
    if (const int i = map_->findText(QString::fromStdString(layers_.overlayMap().name())); i >= 0) map_->setCurrentIndex(i);
    updating_ = false;
}

void LayersPanel::refreshLegend() {
    updating_ = true;
    if (statisticsImage_.lock() != layers_.base() || statisticsLabels_.lock() != layers_.labelsReader())
        statistics_ = std::make_shared<core::LabelStatistics>();
    legend_->clear();
    const auto& table = layers_.labelTable();
    if (layers_.hasLabels())
        for (const auto& [label, e] : table.entries()) {
            if (table.entries().size() > 64 && !layers_.labelsSeen().count(label)) continue;
            auto* item = new QTreeWidgetItem(legend_, {QString::number(label), QString::fromStdString(e.name)});
            if (const auto row = statistics_->rows.find(label); row != statistics_->rows.end()) {
                item->setText(2, QString::number(row->second.volumeMl, 'f', 2));
                if (row->second.sampled > 0)  // "≈" where bricks stored without values made it approximate
                    item->setText(3, QStringLiteral("%1%2 \u00b1 %3 %4")
                                         .arg(row->second.exact ? QString() : QStringLiteral("\u2248"))
                                         .arg(row->second.mean, 0, 'f', 1)
                                         .arg(row->second.sd, 0, 'f', 1)
                                         .arg(QString::fromStdString(statistics_->units)));
            }
            QPixmap swatch(12, 12);
            swatch.fill(QColor(e.rgba[0], e.rgba[1], e.rgba[2]));
            item->setIcon(0, QIcon(swatch));
            item->setData(0, Qt::UserRole, label);
            item->setCheckState(0, e.visible ? Qt::Checked : Qt::Unchecked);
        }
    if (!layers_.labelsNotInTable().empty()) {
        QStringList missing;
        for (const int l : layers_.labelsNotInTable()) missing << QString::number(l);
        show(tr("Label(s) %1 are not in the colour table: drawn in generated colours.").arg(missing.join(", ")), false);
    }
    updating_ = false;
}

}  // namespace hvx::ui
