#include "ui/MeasurementsPanel.h"

#include <QComboBox>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QKeyEvent>
#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <set>

#include "core/base/AtomicFileWriter.h"
#include "ui/MeasurementOverlay.h"

namespace hvx::ui {

namespace {
QString value(const core::Measurement& m, bool spacingAssumed) {
    if (m.kind == core::Measurement::Kind::Distance) return MeasurementOverlay::lengthText(m.lengthMm(), spacingAssumed);
    if (m.kind == core::Measurement::Kind::Angle) return QStringLiteral("%1\u00b0").arg(m.angleDegrees(), 0, 'f', 1);
    if (!m.stats) return QObject::tr("no statistics");
    const auto& s = *m.stats;
    const QString units = s.units.empty() ? QString() : QStringLiteral(" ") + QString::fromStdString(s.units);
    QString text = QObject::tr("mean %1%2 \u00b1 %3, min %4, max %5, %6 voxels")
                       .arg(s.mean, 0, 'f', 1)
                       .arg(units)
                       .arg(s.sd, 0, 'f', 1)
                       .arg(s.min, 0, 'g', 6)
                       .arg(s.max, 0, 'g', 6)
                       .arg(qulonglong(s.voxels));
    if (s.areaMm2 > 0) text += QObject::tr(", %1 mm\u00b2").arg(s.areaMm2, 0, 'f', 1);
    if (!s.exact) text += QObject::tr(" (approximate: %1)").arg(QString::fromStdString(s.note));
    else if (!s.note.empty()) text += QStringLiteral(" (%1)").arg(QString::fromStdString(s.note));
    return text;
}

QString where(const core::Measurement& m) {
    const glm::dvec3 p = m.region ? m.region->centre : m.kind == core::Measurement::Kind::Angle ? m.b : m.a;
    return QStringLiteral("(%1, %2, %3)").arg(p.x, 0, 'f', 1).arg(p.y, 0, 'f', 1).arg(p.z, 0, 'f', 1);
}
}  // namespace

MeasurementsPanel::MeasurementsPanel(QWidget* parent)
    : QWidget(parent), table_(new QTableWidget(0, 5, this)), status_(new QLabel(this)), shape_(new QComboBox(this)) {
    shape_->setObjectName("regionShape");
    shape_->addItems({tr("Circle"), tr("Ellipse"), tr("Rectangle"), tr("Freehand")});
    shape_->setToolTip(tr("What Ctrl-drag draws in the slice views: a circle from its centre, an ellipse or a "
                          "rectangle corner to corner, or a freehand outline (also Ctrl+Shift-drag)"));
    table_->setObjectName("measurementsTable");
    table_->setHorizontalHeaderLabels({tr("Label"), tr("Kind"), tr("View"), tr("Value"), tr("Where (LPS mm)")});
    table_->horizontalHeader()->setStretchLastSection(true);
    table_->setSelectionBehavior(QAbstractItemView::SelectRows);
    table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    table_->verticalHeader()->hide();
    status_->setWordWrap(true);
    auto* remove = new QPushButton(tr("Delete"), this);
    remove->setObjectName("measurementsDelete");
    remove->setToolTip(tr("Remove the selected measurements (Del)"));
    auto* csv = new QPushButton(tr("Export CSV\u2026"), this);
    auto* json = new QPushButton(tr("Export JSON\u2026"), this);
    csv->setToolTip(tr("One row per measurement, with the patient, study and series UIDs and LPS coordinates"));
    json->setToolTip(tr("The list with the patient, study and series UIDs and LPS coordinates"));
    auto* buttons = new QHBoxLayout;
    buttons->addWidget(new QLabel(tr("Ctrl-drag draws"), this));
    buttons->addWidget(shape_);
    buttons->addWidget(remove);
    buttons->addStretch();
    buttons->addWidget(csv);
    buttons->addWidget(json);
    auto* layout = new QVBoxLayout(this);
    layout->addWidget(table_);
    layout->addLayout(buttons);
    layout->addWidget(status_);
    connect(remove, &QPushButton::clicked, this, &MeasurementsPanel::removeSelected);
    connect(shape_, &QComboBox::currentIndexChanged, this, [this] { emit regionShapeChosen(regionShape()); });
    connect(csv, &QPushButton::clicked, this, [this] { exportWithDialog(tr("CSV (*.csv)")); });
    connect(json, &QPushButton::clicked, this, [this] { exportWithDialog(tr("JSON (*.json)")); });
}

void MeasurementsPanel::setVolume(const core::MeasurementSource& source, const core::MeasurementList& list) {
    source_ = source;
    list_ = list;
    status_->clear();
    refresh();
}

void MeasurementsPanel::add(const core::Measurement& m) {
    list_.add(m);
    refresh();
    table_->selectRow(table_->rowCount() - 1);
    emit changed();
}

bool MeasurementsPanel::replace(const core::Measurement& m) {
    if (!list_.replace(m)) return false;
    refresh();
    emit changed();
    return true;
}

RegionShape MeasurementsPanel::regionShape() const { return RegionShape(std::max(0, shape_->currentIndex())); }

int MeasurementsPanel::removeSelected() {
    std::set<int> rows;
    for (const auto* item : table_->selectedItems()) rows.insert(item->row());
    std::vector<std::string> labels;
    for (int r : rows) labels.push_back(table_->item(r, 0)->text().toStdString());
    for (const auto& l : labels) list_.remove(l);
    refresh();
    if (!labels.empty()) emit changed();
    return int(labels.size());
}

bool MeasurementsPanel::remove(const std::string& label) {
    if (!list_.remove(label)) return false;
    refresh();
    emit changed();
    return true;
}

void MeasurementsPanel::refresh() {
    table_->setRowCount(int(list_.items().size()));
    int row = 0;
    for (const auto& m : list_.items()) {
        const QString kind = m.kind == core::Measurement::Kind::Distance ? tr("distance")
                             : m.kind == core::Measurement::Kind::Angle  ? tr("angle")
                             : m.region && m.region->kind == core::MeasureRegion::Kind::Disc ? tr("circle")
                             : m.region && m.region->kind == core::MeasureRegion::Kind::Polygon ? tr("outline")
                             : m.region && m.region->kind == core::MeasureRegion::Kind::Ellipse ? tr("ellipse")
                             : m.region && m.region->kind == core::MeasureRegion::Kind::Rectangle ? tr("rectangle")
                             : m.region && m.region->kind == core::MeasureRegion::Kind::Sphere ? tr("sphere")
                                                                                             : tr("region");
        const QStringList cells{QString::fromStdString(m.label), kind, QString::fromStdString(m.view),
                                value(m, source_.spacingAssumed), where(m)};
        for (int c = 0; c < cells.size(); ++c) table_->setItem(row, c, new QTableWidgetItem(cells[c]));
        ++row;
    }
    table_->resizeColumnsToContents();
}

QString MeasurementsPanel::exportTo(const QString& path) const {
    const std::string text = path.endsWith(".json", Qt::CaseInsensitive) ? list_.toJson(source_) : list_.toCsv(source_);
    try {
        core::AtomicFileWriter out(path.toStdString());  // never a half-written file
        out.append(text.data(), text.size());
        out.commit();
    } catch (const std::exception& e) {
        return QString::fromStdString(e.what());
    }
    return {};
}

void MeasurementsPanel::exportWithDialog(const QString& filter) {
    const QString path = QFileDialog::getSaveFileName(this, tr("Export measurements"), QString(), filter);
    if (path.isEmpty()) return;
    const QString error = exportTo(path);
    status_->setText(error.isEmpty() ? tr("Exported %n measurement(s) to %1", nullptr, int(list_.items().size())).arg(path)
                                     : error);
}

void MeasurementsPanel::keyPressEvent(QKeyEvent* e) {
    if (e->key() == Qt::Key_Delete || e->key() == Qt::Key_Backspace) {
        removeSelected();
        return;
    }
    QWidget::keyPressEvent(e);
}

}  // namespace hvx::ui
