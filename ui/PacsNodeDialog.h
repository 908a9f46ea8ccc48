#pragma once
#include <QDialog>

#include "dicom/PacsSettings.h"

class QLineEdit;
class QSpinBox;
class QComboBox;
class QCheckBox;
class QLabel;
class QFormLayout;

namespace hvx::ui {

/// Edits one PACS node — a DICOM node (name, AE title, host, port, C-GET or C-MOVE, TLS files)
/// or a DICOMweb node (base URL, bearer token or user name and password) — with an Echo button
/// that tests it with the values as typed (C-ECHO, or a QIDO-RS search) and says in plain words
/// what to check when it fails. Settings the dialog does not show are kept.
///
/// Threading: GUI thread only (the echo blocks for at most the network timeout).
class PacsNodeDialog : public QDialog {
    Q_OBJECT
public:
    PacsNodeDialog(const dicom::PacsSettings& settings, const dicom::PacsNode& node, QWidget* parent = nullptr);
    /// The node as typed; throws core::Error for an empty name or AE title, an AE title over 16
    /// characters, or a DICOMweb URL that is not an http(s) URL.
    dicom::PacsNode node() const;
    /// Runs C-ECHO with the typed values; returns the message shown.
    QString echo();

private:
    void showKind();

    dicom::PacsSettings settings_;
    dicom::PacsNode original_;
    QComboBox* kind_;
    QLineEdit* url_;
    QLineEdit* token_;
    QLineEdit* user_;
    QLineEdit* password_;
    QFormLayout* form_;
    QLineEdit* name_;
    QLineEdit* ae_;
    QLineEdit* host_;
    QSpinBox* port_;
    QComboBox* method_;
    QCheckBox* tls_;
    QLineEdit* ca_;
    QLabel* result_;
};

}  // namespace hvx::ui
