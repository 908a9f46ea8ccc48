#pragma once
#include <QWidget>

#include "core/reference/MeasurementList.h"
#include "ui/SliceMeasuring.h"

class QComboBox;
class QTableWidget;
class QLabel;

namespace hvx::ui {

/// The measurements of the open volume, in a dock: one row each (label, kind, view, value,
/// where in LPS mm), Del (or the Delete button) removes the selected ones, and the list is
/// exported as CSV or JSON with the patient, study and series UIDs. A chooser says what Ctrl-drag
/// draws in the slice views (circle, ellipse, rectangle, freehand). The main window keeps the
/// list with the session, per volume.
///
/// Threading: GUI thread only.
class MeasurementsPanel : public QWidget {
    Q_OBJECT
public:
    explicit MeasurementsPanel(QWidget* parent = nullptr);
    /// A new volume: its identity for the exports, and its saved list (or none).
    void setVolume(const core::MeasurementSource& source, const core::MeasurementList& list);
    void add(const core::Measurement& m);
    /// A measurement edited in a view (by its label); false when the list has none of that label.
    bool replace(const core::Measurement& m);
    /// What Ctrl-drag draws in the slice views.
    RegionShape regionShape() const;
    QComboBox* shapeChooser() const { return shape_; }
    /// Removes the selected rows; returns how many.
    int removeSelected();
    /// Removes the measurement with this label (Del in a slice view); false when there is none.
    bool remove(const std::string& label);
    const core::MeasurementList& list() const { return list_; }
    /// Writes the list as CSV, or as JSON when the name ends in .json. Returns an error
    /// sentence, or an empty string when written.
    QString exportTo(const QString& path) const;
    QTableWidget* table() const { return table_; }

signals:
    /// The list changed (a measurement added, edited or removed).
    void changed();
    /// The user chose what Ctrl-drag draws.
    void regionShapeChosen(hvx::ui::RegionShape shape);

protected:
    void keyPressEvent(QKeyEvent* e) override;

private:
    void refresh();
    void exportWithDialog(const QString& filter);

    QTableWidget* table_;
    QLabel* status_;
    QComboBox* shape_;
    core::MeasurementList list_;
    core::MeasurementSource source_;
};

}  // namespace hvx::ui
