#include "ui/PacsPanel.h"

#include <QComboBox>
#include <QDate>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QCheckBox>
#include <QSettings>
#include <QLabel>
#include <QLineEdit>
#include <QPointer>
#include <QPushButton>
#include <QTreeWidget>
#include <QVBoxLayout>

#include <filesystem>

#include "core/base/Error.h"
#include "dicom/PacsClient.h"
#include "dicom/RetrieveJob.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StudyDatabase.h"
#include "ui/JobManager.h"
#include "ui/PacsNodeDialog.h"

namespace hvx::ui {

namespace {
enum Role { StudyUidRole = Qt::UserRole + 1, SeriesUidRole, ExpandedRole };
QString q(const std::string& s) { return QString::fromStdString(s); }
}  // namespace

PacsPanel::PacsPanel(JobManager& jobs, QString settingsPath, QString databasePath, QWidget* parent)
    : QWidget(parent), jobs_(jobs), settingsPath_(std::move(settingsPath)), dbPath_(std::move(databasePath)),
      nodes_(new QComboBox(this)), patient_(new QLineEdit(this)), patientId_(new QLineEdit(this)),
      dates_(new QLineEdit(this)), quick_(new QComboBox(this)), modality_(new QLineEdit(this)),
      accession_(new QLineEdit(this)), results_(new QTreeWidget(this)), status_(new QLabel(this)),
      demo_(new QLabel(this)), keepDemo_(new QCheckBox(tr("Keep the demo archive running when Holovox quits"), this)) {
    demo_->setObjectName("demoStatus");
    demo_->setWordWrap(true);
    demo_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    keepDemo_->setObjectName("keepDemoRunning");
    keepDemo_->setChecked(keepDemoRunning());
    keepDemo_->setToolTip(tr("Otherwise the demo archive Holovox started is stopped on quit "
                             "(holovox-cli demo --stop stops it by hand)"));
    demo_->hide();
    keepDemo_->hide();
    connect(keepDemo_, &QCheckBox::toggled, this, [](bool on) { QSettings().setValue("demo/keepRunning", on); });
    nodes_->setObjectName("pacsNodes");
    nodes_->setToolTip(tr("The PACS to query"));
    auto* edit = new QPushButton(tr("Settings\u2026"), this);
    edit->setToolTip(tr("Edit the node (AE title, host, port, method) and test it with Echo"));
    patient_->setPlaceholderText(tr("e.g. DOE^J*"));
    dates_->setPlaceholderText(tr("YYYYMMDD or YYYYMMDD-YYYYMMDD"));
    quick_->addItems({tr("Any date"), tr("Today"), tr("Yesterday"), tr("Last 7 days"), tr("Last 30 days"), tr("Last year")});
    modality_->setPlaceholderText(tr("CT, MR, \u2026"));
    auto* searchButton = new QPushButton(tr("Search"), this);
    searchButton->setObjectName("pacsSearch");
    auto* retrieveButton = new QPushButton(tr("Retrieve"), this);
    retrieveButton->setObjectName("pacsRetrieve");
    retrieveButton->setToolTip(tr("Retrieve the selected studies or series into the local database"));
    results_->setHeaderLabels({tr("Patient / study / series"), tr("ID"), tr("Date"), tr("Modality"), tr("Accession")});
    // Columns fit their contents (a narrow dock scrolls rather than cutting names short).
    results_->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
    results_->header()->setStretchLastSection(true);
    results_->setSelectionMode(QAbstractItemView::ExtendedSelection);
    status_->setWordWrap(true);
    status_->setTextInteractionFlags(Qt::TextSelectableByMouse);

    auto* nodeRow = new QHBoxLayout;
    nodeRow->addWidget(nodes_, 1);
    nodeRow->addWidget(edit);
    auto* dateRow = new QHBoxLayout;
    dateRow->addWidget(dates_, 1);
    dateRow->addWidget(quick_);
    auto* form = new QFormLayout;
    form->addRow(tr("Node"), nodeRow);
    form->addRow(tr("Patient name"), patient_);
    form->addRow(tr("Patient ID"), patientId_);
    form->addRow(tr("Study date"), dateRow);
    form->addRow(tr("Modality"), modality_);
    form->addRow(tr("Accession"), accession_);
    auto* buttons = new QHBoxLayout;
    buttons->addStretch(1);
    buttons->addWidget(searchButton);
    buttons->addWidget(retrieveButton);
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(4, 4, 4, 4);
    layout->addLayout(form);
    layout->addLayout(buttons);
    layout->addWidget(results_, 1);
    layout->addWidget(status_);
    layout->addWidget(demo_);
    layout->addWidget(keepDemo_);
    connect(edit, &QPushButton::clicked, this, &PacsPanel::editNode);
    connect(searchButton, &QPushButton::clicked, this, &PacsPanel::search);
    connect(retrieveButton, &QPushButton::clicked, this, &PacsPanel::retrieveSelected);
    for (auto* field : {patient_, patientId_, dates_, modality_, accession_})
        connect(field, &QLineEdit::returnPressed, this, &PacsPanel::search);
    connect(quick_, &QComboBox::activated, this, &PacsPanel::applyQuickRange);
    connect(results_, &QTreeWidget::itemExpanded, this, &PacsPanel::expandStudy);
    connect(&jobs_, &JobManager::finished, this, [this](int id, const QString& state, const QString& message) {
        if (myJobs_.remove(id) && state == "failed") showError(message);
    });
    reloadSettings();
}

void PacsPanel::reloadSettings() {
    nodes_->clear();
    try {
        settings_ = dicom::PacsSettings::load(settingsPath_.toStdString());
        for (const auto& n : settings_.nodes) nodes_->addItem(q(n.name));
        if (!settings_.defaultNode.empty()) nodes_->setCurrentText(q(settings_.defaultNode));
        status_->clear();
    } catch (const core::Error& e) {
        showError(q(e.what()));
    }
}

QString PacsPanel::errorText() const { return status_->text(); }

void PacsPanel::setDemoStatus(const QString& status) {
    demo_->setText(tr("Demo archive: %1").arg(status));
    demo_->setStyleSheet(status.startsWith("failed") ? "color: #c33" : QString());
    demo_->show();
    keepDemo_->show();
}

QString PacsPanel::demoStatus() const { return demo_->text(); }

bool PacsPanel::keepDemoRunning() { return QSettings().value("demo/keepRunning", false).toBool(); }

void PacsPanel::showError(const QString& message) {
    status_->setStyleSheet("color: #c33");
    status_->setText(message);
}

void PacsPanel::applyQuickRange(int index) {
    const QDate today = QDate::currentDate();
    const auto fmt = [](const QDate& d) { return d.toString("yyyyMMdd"); };
    switch (index) {
    case 1: dates_->setText(fmt(today)); break;
    case 2: dates_->setText(fmt(today.addDays(-1))); break;
    case 3: dates_->setText(fmt(today.addDays(-6)) + "-" + fmt(today)); break;
    case 4: dates_->setText(fmt(today.addDays(-29)) + "-" + fmt(today)); break;
    case 5: dates_->setText(fmt(today.addYears(-1)) + "-" + fmt(today)); break;
    default: dates_->clear();
    }
}

void PacsPanel::editNode() {
    dicom::PacsNode node;
    try {
        node = settings_.node(nodes_->currentText().toStdString());
    } catch (const core::Error&) {
        node.name = "pacs";
        node.host = "127.0.0.1";
    }
    PacsNodeDialog dialog(settings_, node, this);
    if (dialog.exec() != QDialog::Accepted) return;
    try {
        settings_.upsert(dialog.node());
        settings_.save(settingsPath_.toStdString());
        reloadSettings();
        nodes_->setCurrentText(q(dialog.node().name));
    } catch (const core::Error& e) {
        showError(q(e.what()));
    }
}

int PacsPanel::search() {
    results_->clear();
    status_->setStyleSheet({});
    dicom::PacsNode node;
    try {
        node = settings_.node(nodes_->currentText().toStdString());
    } catch (const core::Error& e) {
        showError(q(e.what()) + tr(" \u2014 add a node with Settings\u2026"));
        return -1;
    }
    dicom::QueryKeys keys;
    keys.patientName = patient_->text().trimmed().toStdString();
    keys.patientId = patientId_->text().trimmed().toStdString();
    keys.studyDate = dates_->text().trimmed().toStdString();
    keys.modality = modality_->text().trimmed().toUpper().toStdString();
    keys.accessionNumber = accession_->text().trimmed().toStdString();
    status_->setText(tr("Searching %1\u2026").arg(q(node.name)));
    QPointer<PacsPanel> self(this);
    const auto local = settings_.local;
    JobManager* jobs = &jobs_;
    return track(jobs_.start(
        tr("Search %1").arg(q(node.name)),
        [self, jobs, local, node, keys](core::JobContext& job) {
            dicom::PacsClient client(local, node);
            const auto n = client.find(dicom::QueryLevel::Study, keys, [&](const dicom::QueryResult& r) {
                jobs->post([self, r] {  // each answer as it arrives
                    if (!self) return;
                    auto* item = new QTreeWidgetItem(self->results_, {q(r.patientName).replace('^', ' ') + QStringLiteral(" \u2014 ") + q(r.studyDescription),
                                                                      q(r.patientId), q(r.studyDate), q(r.modalitiesInStudy),
                                                                      q(r.accessionNumber)});
                    item->setData(0, StudyUidRole, q(r.studyUid));
                    item->setChildIndicatorPolicy(QTreeWidgetItem::ShowIndicator);
                });
                return !job.cancelled();
            });
            return QObject::tr("%n studies found", nullptr, int(n));
        },
        [self](const QString& summary) {
            if (self) self->status_->setText(summary);
        }));
}

int PacsPanel::track(int jobId) {
    myJobs_.insert(jobId);
    return jobId;
}

void PacsPanel::expandStudy(QTreeWidgetItem* item) {
    if (item->parent() || item->data(0, ExpandedRole).toBool()) return;
    item->setData(0, ExpandedRole, true);
    dicom::PacsNode node;
    try {
        node = settings_.node(nodes_->currentText().toStdString());
    } catch (const core::Error& e) {
        showError(q(e.what()));
        return;
    }
    dicom::QueryKeys keys;
    keys.studyUid = item->data(0, StudyUidRole).toString().toStdString();
    QPointer<PacsPanel> self(this);
    const QString studyUid = item->data(0, StudyUidRole).toString();
    const auto local = settings_.local;
    JobManager* jobs = &jobs_;
    track(jobs_.start(tr("Series of a study on %1").arg(q(node.name)), [self, jobs, local, node, keys, studyUid](core::JobContext&) {
        dicom::PacsClient client(local, node);
        client.find(dicom::QueryLevel::Series, keys, [&](const dicom::QueryResult& r) {
            jobs->post([self, r, studyUid] {
                if (!self) return;
                for (int i = 0; i < self->results_->topLevelItemCount(); ++i) {
                    auto* study = self->results_->topLevelItem(i);
                    if (study->data(0, StudyUidRole).toString() != studyUid) continue;
                    auto* s = new QTreeWidgetItem(study, {QStringLiteral("#%1 %2").arg(r.seriesNumber).arg(q(r.seriesDescription)),
                                                          {}, {}, q(r.modality), {}});
                    s->setData(0, StudyUidRole, studyUid);
                    s->setData(0, SeriesUidRole, q(r.seriesUid));
                }
            });
            return true;
        });
        return QString();
    }));
}

QList<int> PacsPanel::retrieveSelected() {
    QList<int> ids;
    dicom::PacsNode node;
    try {
        node = settings_.node(nodes_->currentText().toStdString());
    } catch (const core::Error& e) {
        showError(q(e.what()));
        return ids;
    }
    const auto selected = results_->selectedItems();
    if (selected.isEmpty()) {
        showError(tr("Select a study or a series to retrieve"));
        return ids;
    }
    status_->setStyleSheet({});
    QPointer<PacsPanel> self(this);
    for (auto* item : selected) {
        const std::string study = item->data(0, StudyUidRole).toString().toStdString();
        const std::string series = item->data(0, SeriesUidRole).toString().toStdString();
        const auto settings = settings_;
        const std::string db = dbPath_.toStdString();
        ids << jobs_.start(
            tr("Retrieve %1").arg(item->text(0)),
            [settings, node, study, series, db](core::JobContext& job) {
                dicom::StudyDatabase database(db);
                dicom::RetrieveJob retrieve(settings, node, database, dicom::SeriesOctree::folderFor(db));
                const auto statuses = retrieve.run(study, series, true, job, [&](const dicom::SeriesRetrieveStatus& s) {
                    const auto& p = s.progress;
                    const int total = p.completed + p.remaining + p.failed + p.warning;
                    // The fraction is the whole retrieve's (several series run at once).
                    job.report(job.progress().fraction,
                               s.description + ": " + std::to_string(p.completed) +
                                   (total > 0 ? "/" + std::to_string(total) : std::string()));
                });
                QStringList errors;
                for (const auto& s : statuses)
                    if (!s.error.empty()) errors << q(s.description + ": " + s.error);
                if (!errors.isEmpty() && errors.size() == int(statuses.size())) throw core::Error(errors.join("; ").toStdString());
                return QObject::tr("%n series retrieved", nullptr, int(statuses.size()) - int(errors.size())) +
                       (errors.isEmpty() ? QString() : QStringLiteral(" (") + errors.join("; ") + ")");
            },
            [self](const QString& summary) {
                if (!self) return;
                self->status_->setText(summary);
                emit self->retrieved(summary);
            });
    }
    for (int id : ids) myJobs_.insert(id);
    return ids;
}

}  // namespace hvx::ui
