#include "ui/PacsNodeDialog.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPushButton>
#include <QSpinBox>

#include "core/base/Error.h"
#include "dicom/PacsClient.h"

namespace hvx::ui {

PacsNodeDialog::PacsNodeDialog(const dicom::PacsSettings& settings, const dicom::PacsNode& node, QWidget* parent)
    : QDialog(parent), settings_(settings), name_(new QLineEdit(QString::fromStdString(node.name))),
      ae_(new QLineEdit(QString::fromStdString(node.aeTitle))), host_(new QLineEdit(QString::fromStdString(node.host))),
      port_(new QSpinBox), method_(new QComboBox), tls_(new QCheckBox(tr("DICOM over TLS"))),
      ca_(new QLineEdit(QString::fromStdString(node.tlsTrustedCertificate))), result_(new QLabel) {
    setWindowTitle(tr("PACS node"));
    ae_->setMaxLength(16);
    ae_->setToolTip(tr("The node's called AE title (at most 16 characters)"));
    port_->setRange(1, 65535);
    port_->setValue(node.port);
    method_->addItems({tr("C-GET (no inbound connection needed)"), tr("C-MOVE (to Holovox's storage SCP)")});
    method_->setCurrentIndex(node.retrieve == dicom::RetrieveMethod::Move ? 1 : 0);
    tls_->setChecked(node.tls);
    ca_->setPlaceholderText(tr("PEM file of the CA that signs the node's certificate"));
    result_->setWordWrap(true);
    auto* form = new QFormLayout(this);
    form->addRow(tr("Name"), name_);
    form->addRow(tr("AE title"), ae_);
    form->addRow(tr("Host"), host_);
    form->addRow(tr("Port"), port_);
    form->addRow(tr("Retrieve by"), method_);
    form->addRow(QString(), tls_);
    form->addRow(tr("Trusted CA"), ca_);
    auto* echoButton = new QPushButton(tr("Echo"));
    echoButton->setObjectName("echoButton");
    echoButton->setToolTip(tr("Test the connection (C-ECHO) with these values"));
    form->addRow(echoButton, result_);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
    form->addRow(buttons);
    connect(echoButton, &QPushButton::clicked, this, &PacsNodeDialog::echo);
    connect(buttons, &QDialogButtonBox::accepted, this, [this] {
        try {
            this->node();  // validates
            accept();
        } catch (const core::Error& e) {
            QMessageBox::warning(this, tr("PACS node"), QString::fromStdString(e.what()));
        }
    });
    connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
}

dicom::PacsNode PacsNodeDialog::node() const {
    dicom::PacsNode n;
    n.name = name_->text().trimmed().toStdString();
    n.aeTitle = ae_->text().trimmed().toStdString();
    n.host = host_->text().trimmed().toStdString();
    n.port = std::uint16_t(port_->value());
    n.retrieve = method_->currentIndex() == 1 ? dicom::RetrieveMethod::Move : dicom::RetrieveMethod::Get;
    n.tls = tls_->isChecked();
    n.tlsTrustedCertificate = ca_->text().trimmed().toStdString();
    if (n.name.empty()) throw core::Error("the node needs a name");
    if (n.aeTitle.empty() || n.aeTitle.size() > 16) throw core::Error("the AE title must have 1 to 16 characters");
    if (n.host.empty()) throw core::Error("the node needs a host name or address");
    return n;
}

QString PacsNodeDialog::echo() {
    try {
        dicom::PacsClient client(settings_.local, node());
        client.echo();
        result_->setText(tr("<span style='color:#2a2'>Echo succeeded</span>"));
    } catch (const core::Error& e) {
        result_->setText(QStringLiteral("<span style='color:#c33'>%1</span>").arg(QString::fromStdString(e.what()).toHtmlEscaped()));
    }
    return result_->text();
}

}  // namespace hvx::ui
