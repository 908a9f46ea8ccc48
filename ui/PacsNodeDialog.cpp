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
#include "dicom/DicomWebUrl.h"
#include "dicom/PacsClient.h"

namespace hvx::ui {

PacsNodeDialog::PacsNodeDialog(const dicom::PacsSettings& settings, const dicom::PacsNode& node, QWidget* parent)
    : QDialog(parent), settings_(settings), original_(node), kind_(new QComboBox),
      url_(new QLineEdit(QString::fromStdString(node.baseUrl))), token_(new QLineEdit(QString::fromStdString(node.bearerToken))),
      user_(new QLineEdit(QString::fromStdString(node.username))), password_(new QLineEdit(QString::fromStdString(node.password))),
      form_(nullptr), name_(new QLineEdit(QString::fromStdString(node.name))),
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
    kind_->setObjectName("nodeKind");
    kind_->addItems({tr("DICOM (C-FIND, C-GET, C-MOVE)"), tr("DICOMweb (QIDO-RS, WADO-RS, STOW-RS)")});
    kind_->setCurrentIndex(node.kind == dicom::NodeKind::DicomWeb ? 1 : 0);
    url_->setObjectName("nodeUrl");
    url_->setPlaceholderText(tr("http://host:8042/dicom-web"));
    token_->setPlaceholderText(tr("optional: sent as 'Authorization: Bearer \u2026'"));
    user_->setPlaceholderText(tr("optional: HTTP basic authentication"));
    password_->setEchoMode(QLineEdit::Password);
    auto* form = new QFormLayout(this);
    form_ = form;
    form->addRow(tr("Name"), name_);
    form->addRow(tr("Protocol"), kind_);
    form->addRow(tr("Base URL"), url_);
    form->addRow(tr("Bearer token"), token_);
    form->addRow(tr("User name"), user_);
    form->addRow(tr("Password"), password_);
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
    connect(kind_, &QComboBox::currentIndexChanged, this, &PacsNodeDialog::showKind);
    showKind();
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

void PacsNodeDialog::showKind() {
    const bool web = kind_->currentIndex() == 1;
    for (QWidget* w : std::initializer_list<QWidget*>{url_, token_, user_, password_}) form_->setRowVisible(w, web);
    for (QWidget* w : std::initializer_list<QWidget*>{ae_, host_, port_, method_, tls_, ca_}) form_->setRowVisible(w, !web);
}

dicom::PacsNode PacsNodeDialog::node() const {
    dicom::PacsNode n = original_;  // what the dialog does not show (PDU size, our TLS key) is kept
    n.name = name_->text().trimmed().toStdString();
    if (n.name.empty()) throw core::Error("the node needs a name");
    if (kind_->currentIndex() == 1) {
        n.kind = dicom::NodeKind::DicomWeb;
        n.baseUrl = url_->text().trimmed().toStdString();
        dicom::DicomWebUrl::check(n.baseUrl, "the base URL");
        n.bearerToken = token_->text().trimmed().toStdString();
        n.username = user_->text().trimmed().toStdString();
        n.password = password_->text().toStdString();
        if (!n.bearerToken.empty() && !n.username.empty()) throw core::Error("give a bearer token or a user name, not both");
        return n;
    }
    n.kind = dicom::NodeKind::Dimse;
    n.aeTitle = ae_->text().trimmed().toStdString();
    n.host = host_->text().trimmed().toStdString();
    n.port = std::uint16_t(port_->value());
    n.retrieve = method_->currentIndex() == 1 ? dicom::RetrieveMethod::Move : dicom::RetrieveMethod::Get;
    n.tls = tls_->isChecked();
    n.tlsTrustedCertificate = ca_->text().trimmed().toStdString();
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
