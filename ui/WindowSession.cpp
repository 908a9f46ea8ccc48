#include "ui/WindowSession.h"

#include <QSettings>

#include <algorithm>

#include "core/base/Error.h"
#include "ui/MainWindow.h"
#include "ui/RenderControls.h"

namespace hvx::ui {

QStringList WindowSession::restore(MainWindow& window) {
    QStringList ignored;
    QSettings settings;
    window.restoreGeometry(settings.value("window/geometry").toByteArray());
    window.restoreState(settings.value("window/state").toByteArray());
    if (settings.contains("tools/json")) {
        try {
            window.setTools(core::ToolSet::fromJson(settings.value("tools/json").toString().toStdString()));
        } catch (const core::Error& e) {
            ignored << QObject::tr("Saved tools ignored: %1").arg(QString::fromStdString(e.what()));
        }
    }
    if (settings.contains("render/mode")) {
        auto rs = window.renderControls()->settings();
        rs.mode = core::RenderSettings::Mode(std::clamp(settings.value("render/mode").toInt(), 0, 4));
        window.renderControls()->setSettings(rs);
    }
    return ignored;
}

void WindowSession::save(const MainWindow& window) {
    QSettings settings;
    settings.setValue("window/geometry", window.saveGeometry());
    settings.setValue("window/state", window.saveState());
    settings.setValue("render/mode", int(window.renderControls()->settings().mode));
    settings.setValue("tools/json", QString::fromStdString(window.tools().toJson()));
}

}  // namespace hvx::ui
