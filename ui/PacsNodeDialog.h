#pragma once
#include <QDialog>

#include "dicom/PacsSettings.h"

class QLineEdit;
class QSpinBox;
class QComboBox;
class QCheckBox;
class QLabel;

namespace hvx::ui {

/// Edits one PACS node (name, AE title, host, port, C-GET or C-MOVE, TLS files) with an Echo
/// button that tests the association with the values as typed and says in plain words what
/// to check when it fails.
///
/// Threading: GUI thread only (the echo blocks for at most the network timeout).
class PacsNodeDialog : public QDialog {
    Q_OBJECT
public:
    PacsNodeDialog(const dicom::PacsSettings& settings, const dicom::PacsNode& node, QWidget* parent = nullptr);
    /// The node as typed; throws core::Error for an empty name or AE title, or an AE title over 16 characters.
    dicom::PacsNode node() const;
    /// Runs C-ECHO with the typed values; returns the message shown.
    QString echo();

private:
    dicom::PacsSettings settings_;
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
