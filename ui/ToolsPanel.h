#pragma once
#include <QWidget>

#include <functional>
#include <vector>

#include "core/appearance/ToolSet.h"

class QGroupBox;
class QDoubleSpinBox;

namespace hvx::ui {

/// A dock panel for some of the illustrative tools: Probes (the focal probe and the
/// context-preserving probe), Clip plane, or Band picker (with MImDA). Each tool is a checkable
/// group of numeric fields whose ranges refuse out-of-range values, with a Reset to the thesis's
/// defaults. Several tools can be on at once; every edit emits changed().
///
/// Threading: GUI thread only.
class ToolsPanel : public QWidget {
    Q_OBJECT
public:
    enum class Section { Probes, Clip, Band };
    ToolsPanel(Section section, QWidget* parent = nullptr);
    /// Shows these tools' values (without emitting changed()).
    void setTools(const core::ToolSet& tools);
    /// Writes this panel's tools into `tools`.
    void apply(core::ToolSet& tools) const;
    /// The group box of a tool ("focal", "context", "clip", "band", "mimda"), for tests.
    QGroupBox* group(const QString& name) const;

signals:
    void changed();

private:
    using EnabledFlag = bool& (*)(core::ToolSet&);
    QGroupBox* addGroup(const QString& name, const QString& title, const QString& tip, EnabledFlag enabled);
    QDoubleSpinBox* addField(QGroupBox* group, const QString& label, double lo, double hi, double step, int decimals,
                             const QString& tip = {});
    void reset();

    Section section_;
    std::vector<QGroupBox*> groups_;
    // Reads and writes between the fields and a ToolSet, one pair per field.
    std::vector<std::function<void(const core::ToolSet&)>> show_;
    std::vector<std::function<void(core::ToolSet&)>> read_;
    bool updating_ = false;
};

}  // namespace hvx::ui
