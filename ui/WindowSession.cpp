#include "ui/WindowSession.h"

#include <QSettings>

#include <exception>

#include "core/base/Error.h"
#include "ui/MainWindow.h"
#include "ui/RenderControls.h"

namespace hvx::ui {

QStringList WindowSession::restore(MainWindow& window) {
    // Whatever is saved may be of another type or damaged (another version, a hand edit): each
    // value that cannot be used is reset, with a sentence, and the window starts regardless.
    QStringList ignored;
    QSettings settings;
    auto reset = [&](const QString& key, const QString& why) {
        settings.remove(key);
        ignored << QObject::tr("Saved %1 reset: %2").arg(key, why);
    };
    if (settings.contains("window/geometry") &&
        (!settings.value("window/geometry").canConvert<QByteArray>() ||
         !window.restoreGeometry(settings.value("window/geometry").toByteArray())))
        reset("window/geometry", QObject::tr("not a window geometry"));
    if (settings.contains("window/state") &&
        (!settings.value("window/state").canConvert<QByteArray>() ||
         !window.restoreState(settings.value("window/state").toByteArray())))
        reset("window/state", QObject::tr("not a dock layout"));
    if (settings.contains("tools/json")) {
        try {
            window.setTools(core::ToolSet::fromJson(settings.value("tools/json").toString().toStdString()));
        } catch (const std::exception& e) {
            reset("tools/json", QString::fromStdString(e.what()));
        }
    }
    if (settings.contains("render/mode")) {
        bool ok = false;
        const int mode = settings.value("render/mode").toInt(&ok);
        if (!ok || mode < 0 || mode > 4) {
            reset("render/mode", QObject::tr("not a rendering mode"));
        } else {
            auto rs = window.renderControls()->settings();
            rs.mode = core::RenderSettings::Mode(mode);
            window.renderControls()->setSettings(rs);
        }
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
