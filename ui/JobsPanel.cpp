#include "ui/JobsPanel.h"

#include <QAction>
#include <QApplication>
#include <QClipboard>
#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QHBoxLayout>
#include <QMessageBox>
#include <QFileInfo>
#include <QStandardPaths>
#include <QHeaderView>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>

#include <cmath>

#include "ui/JobManager.h"

namespace hvx::ui {

namespace {
QString eta(double seconds) {
    if (seconds < 0) return QObject::tr("estimating\u2026");
    if (seconds < 60) return QObject::tr("%1 s left").arg(int(std::ceil(seconds)));
    return QObject::tr("%1 min %2 s left").arg(int(seconds) / 60).arg(int(seconds) % 60);
}
}  // namespace

JobsPanel::JobsPanel(JobManager& jobs, QWidget* parent)
    : QWidget(parent), jobs_(jobs), table_(new QTableWidget(0, 4, this)), status_(new QWidget),
      statusLabel_(new QLabel(status_)), statusBar_(new QProgressBar(status_)) {
    table_->setHorizontalHeaderLabels({tr("Job"), tr("Progress"), tr("Status"), QString()});
    table_->horizontalHeader()->setSectionResizeMode(0, QHeaderView::Stretch);
    table_->verticalHeader()->hide();
    table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    table_->setSelectionMode(QAbstractItemView::SingleSelection);
    table_->setSelectionBehavior(QAbstractItemView::SelectRows);
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(2, 2, 2, 2);
    layout->addWidget(table_);
    auto* sl = new QHBoxLayout(status_);
    sl->setContentsMargins(0, 0, 0, 0);
    sl->addWidget(statusLabel_);
    sl->addWidget(statusBar_);
    statusBar_->setMaximumWidth(160);
    statusBar_->setRange(0, 1000);
    status_->setVisible(false);
    table_->setToolTip(tr("Double-click a job for its whole message; right-click or Ctrl+C copies it"));
    table_->setContextMenuPolicy(Qt::ActionsContextMenu);
    auto* copy = new QAction(tr("Copy message"), table_);
    copy->setShortcut(QKeySequence::Copy);
    copy->setShortcutContext(Qt::WidgetShortcut);
    table_->addAction(copy);
    connect(copy, &QAction::triggered, this, [this] {
        if (const int id = idAt(table_->currentRow()); id >= 0) copyDetails(id);
    });
    connect(table_, &QTableWidget::cellDoubleClicked, this, [this](int row, int) {
        if (const int id = idAt(row); id >= 0) showDetails(id);
    });
    connect(&jobs_, &JobManager::started, this, &JobsPanel::onStarted);
    connect(&jobs_, &JobManager::progressed, this, &JobsPanel::onProgress);
    connect(&jobs_, &JobManager::finished, this, &JobsPanel::onFinished);
}

int JobsPanel::rowOf(int id) const {
    const auto it = rows_.find(id);
    return it == rows_.end() ? -1 : it->second;
}

QString JobsPanel::cellText(int id, int column) const {
    const int row = rowOf(id);
    if (row < 0) return {};
    if (column == 1) {
        auto* bar = qobject_cast<QProgressBar*>(table_->cellWidget(row, 1));
        return bar ? QString::number(bar->value() / 10) : QString();
    }
    auto* item = table_->item(row, column);
    return item ? item->text() : QString();
}

void JobsPanel::onStarted(int id, const QString& title) {
    const int row = table_->rowCount();
    table_->insertRow(row);
    rows_[id] = row;
    titles_[id] = title;
    fractions_[id] = 0;
    table_->setItem(row, 0, new QTableWidgetItem(title));
    auto* bar = new QProgressBar;
    bar->setRange(0, 1000);
    table_->setCellWidget(row, 1, bar);
    table_->setItem(row, 2, new QTableWidgetItem(tr("starting")));
    auto* cancel = new QPushButton(tr("Cancel"));
    cancel->setToolTip(tr("Stop this job; nothing already stored is lost"));
    cancel->setObjectName(QStringLiteral("cancelJob%1").arg(id));
    connect(cancel, &QPushButton::clicked, this, [this, id] { jobs_.cancel(id); });
    table_->setCellWidget(row, 3, cancel);
    updateStatus();
}

void JobsPanel::onProgress(int id, double fraction, double etaSeconds, const QString& stage) {
    const int row = rowOf(id);
    if (row < 0) return;
    fractions_[id] = fraction;
    if (auto* bar = qobject_cast<QProgressBar*>(table_->cellWidget(row, 1))) bar->setValue(int(fraction * 1000));
    table_->item(row, 2)->setText(stage.isEmpty() ? eta(etaSeconds) : stage + QStringLiteral(" \u2014 ") + eta(etaSeconds));
    updateStatus();
}

void JobsPanel::onFinished(int id, const QString& state, const QString& message) {
    const int row = rowOf(id);
    if (row < 0) return;
    fractions_.erase(id);
    if (auto* bar = qobject_cast<QProgressBar*>(table_->cellWidget(row, 1)); bar && state == "done") bar->setValue(1000);
    const QString text = state == "done" ? tr("done") : state == "cancelled" ? tr("cancelled") : tr("failed: %1").arg(message);
    table_->item(row, 2)->setText(text);
    table_->item(row, 2)->setToolTip(message.isEmpty() ? text : message);
    outcomes_[id] = text;
    // The job log keeps every outcome, whole, for when the dock has been cleared or the text cut.
    const QString path = logPath();
    QDir().mkpath(QFileInfo(path).absolutePath());
    QFile log(path);
    if (log.open(QIODevice::Append | QIODevice::Text))
        log.write(QStringLiteral("%1  %2: %3\n")
                      .arg(QDateTime::currentDateTime().toString(Qt::ISODate), titles_[id], text)
                      .toUtf8());
    if (auto* cancel = table_->cellWidget(row, 3)) cancel->hide();  // gone at once, deleted by the table
    table_->removeCellWidget(row, 3);
    table_->setItem(row, 3, new QTableWidgetItem(QString()));
    updateStatus();
}

int JobsPanel::idAt(int row) const {
    for (const auto& [id, r] : rows_)
        if (r == row) return id;
    return -1;
}

QString JobsPanel::details(int id) const {
    const auto it = outcomes_.find(id);
    return it != outcomes_.end() ? it->second : cellText(id, 2);
}

void JobsPanel::copyDetails(int id) const {
    const auto title = titles_.find(id);
    QApplication::clipboard()->setText((title != titles_.end() ? title->second + ": " : QString()) + details(id));
}

void JobsPanel::showDetails(int id) {
    auto* box = new QMessageBox(QMessageBox::Information, titles_[id], details(id), QMessageBox::Close, this);
    box->setTextInteractionFlags(Qt::TextSelectableByMouse | Qt::TextSelectableByKeyboard);
    box->setAttribute(Qt::WA_DeleteOnClose);
    box->setObjectName("jobDetails");
    box->open();  // not modal to the application: the jobs go on
}

QString JobsPanel::logPath() {
    return QStandardPaths::writableLocation(QStandardPaths::GenericDataLocation) + "/holovox/jobs.log";
}

void JobsPanel::updateStatus() {
    if (fractions_.empty()) {
        status_->setVisible(false);
        return;
    }
    double sum = 0;
    for (const auto& [id, f] : fractions_) sum += f;
    statusLabel_->setText(fractions_.size() == 1 ? titles_[fractions_.begin()->first]
                                                 : tr("%1 jobs").arg(fractions_.size()));
    statusBar_->setValue(int(sum / double(fractions_.size()) * 1000));
    status_->setVisible(true);
}

}  // namespace hvx::ui
