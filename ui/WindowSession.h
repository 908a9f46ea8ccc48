#pragma once
#include <QStringList>

namespace hvx::ui {

class MainWindow;

/// The workstation's session in QSettings: the window's geometry and dock layout, the
/// rendering mode and the illustrative tools. Saved on close and restored at start.
///
/// Threading: GUI thread.
class WindowSession {
public:
    /// Restores what was saved; a value that cannot be used (wrong type, damaged, out of range)
    /// is removed and named in the sentences returned. Never throws.
    static QStringList restore(MainWindow& window);
    static void save(const MainWindow& window);
};

}  // namespace hvx::ui
