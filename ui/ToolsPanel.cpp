#include "ui/ToolsPanel.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QPushButton>
#include <QVBoxLayout>

namespace hvx::ui {

namespace {
// Binds a spin box to one double of the ToolSet.
template <class Get>
void bind(std::vector<std::function<void(const core::ToolSet&)>>& show, std::vector<std::function<void(core::ToolSet&)>>& read,
          QDoubleSpinBox* box, Get get) {
    show.push_back([box, get](const core::ToolSet& t) { box->setValue(get(const_cast<core::ToolSet&>(t))); });
    read.push_back([box, get](core::ToolSet& t) { get(t) = box->value(); });
}
}  // namespace

ToolsPanel::ToolsPanel(Section section, QWidget* parent) : QWidget(parent), section_(section) {
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(4, 4, 4, 4);
    auto vec3 = [&](QGroupBox* g, const QString& label, auto field, double lo, double hi) {
        const char* axes[] = {" x", " y", " z"};
        for (int a = 0; a < 3; ++a) {
            auto* box = addField(g, label + axes[a], lo, hi, 1.0, 1);
            bind(show_, read_, box, [field, a](core::ToolSet& t) -> double& { return field(t)[a]; });
        }
    };
    auto scalar = [&](QGroupBox* g, const QString& label, auto field, double lo, double hi, double step, int dec,
                      const QString& tip = {}) {
        bind(show_, read_, addField(g, label, lo, hi, step, dec, tip), field);
    };
    if (section == Section::Probes) {
        auto* f = addGroup("focal", tr("Context-preserving focal probe"),
                           tr("Focus: relief shading and silhouette darkening; context: silhouettes and view-dependent "
                              "transparency (thesis \u00a76.3). Ctrl+click in the 3D view places it."),
                           [](core::ToolSet& t) -> bool& { return t.focal.enabled; });
        vec3(f, tr("Centre"), [](core::ToolSet& t) -> glm::dvec3& { return t.focal.centre; }, -5000, 5000);
        vec3(f, tr("Radius"), [](core::ToolSet& t) -> glm::dvec3& { return t.focal.radii; }, 1, 2000);
        vec3(f, tr("Rotation (\u00b0)"), [](core::ToolSet& t) -> glm::dvec3& { return t.focal.rotationDegrees; }, -360, 360);
        scalar(f, "p", [](core::ToolSet& t) -> double& { return t.focal.p; }, 0.5, 64, 0.5, 1, tr("2: sphere or cylinder; 4: rounded cube"));
        scalar(f, "q", [](core::ToolSet& t) -> double& { return t.focal.q; }, 0.5, 64, 0.5, 1, tr("2: sphere; 4: cylinder or rounded cube"));
        scalar(f, "\u03b2", [](core::ToolSet& t) -> double& { return t.focal.beta; }, -20, 20, 0.5, 2);
        scalar(f, "\u03c1", [](core::ToolSet& t) -> double& { return t.focal.rho; }, 0, 0.99, 0.05, 2);
        scalar(f, "g_l", [](core::ToolSet& t) -> double& { return t.focal.gl; }, 0, 1, 0.005, 3);
        scalar(f, "g_h", [](core::ToolSet& t) -> double& { return t.focal.gh; }, 0, 1, 0.05, 3);
        scalar(f, "s_l", [](core::ToolSet& t) -> double& { return t.focal.sl; }, 0, 1, 0.05, 2);
        scalar(f, "s_h", [](core::ToolSet& t) -> double& { return t.focal.sh; }, 0, 1, 0.05, 2);
        scalar(f, tr("Toon a"), [](core::ToolSet& t) -> double& { return t.focal.toon; }, 0, 20, 0.5, 1);
        scalar(f, tr("Context step"), [](core::ToolSet& t) -> double& { return t.focal.contextStep; }, 1, 8, 1, 0,
               tr("Samples a ray steps at a time outside the probe, where it draws only the ghosted context "
                  "(1: every sample). The focus is always sampled in full."));
        auto* c = addGroup("context", tr("Context-preserving probe"),
                           tr("Material turns transparent with penetration; contextual edges show when looking along the "
                              "tool axis (thesis \u00a76.4.2)."),
                           [](core::ToolSet& t) -> bool& { return t.context.enabled; });
        vec3(c, tr("Centre"), [](core::ToolSet& t) -> glm::dvec3& { return t.context.centre; }, -5000, 5000);
        scalar(c, tr("Radius"), [](core::ToolSet& t) -> double& { return t.context.radius; }, 1, 2000, 5, 1);
        vec3(c, tr("Axis"), [](core::ToolSet& t) -> glm::dvec3& { return t.context.axis; }, -1, 1);
    } else if (section == Section::Clip) {
        auto* g = addGroup("clip", tr("Clip plane with view-dependent context"),
                           tr("A cut-away seen face-on; more context appears as the view turns away (thesis \u00a76.4.1)."),
                           [](core::ToolSet& t) -> bool& { return t.clip.enabled; });
        vec3(g, tr("Normal"), [](core::ToolSet& t) -> glm::dvec3& { return t.clip.normal; }, -1, 1);
        scalar(g, tr("Offset (mm)"), [](core::ToolSet& t) -> double& { return t.clip.offset; }, -5000, 5000, 1, 1);
        scalar(g, tr("Slab \u03b4 (mm)"), [](core::ToolSet& t) -> double& { return t.clip.thickness; }, 0, 1000, 1, 1);
        scalar(g, "f_l", [](core::ToolSet& t) -> double& { return t.clip.fl; }, 0, 1, 0.05, 2);
        scalar(g, "f_h", [](core::ToolSet& t) -> double& { return t.clip.fh; }, 0, 1, 0.05, 2);
    } else {
        auto* b = addGroup("band", tr("Band picker"),
                           tr("Importance 1 inside the band; other bands fade when looking along the tool axis "
                              "(thesis \u00a76.4.3). Alt+click in the 3D view picks the band under the cursor."),
                           [](core::ToolSet& t) -> bool& { return t.band.enabled; });
        const char* names[] = {"b0", "b1", "b2", "b3"};
        for (int k = 0; k < 4; ++k)
            scalar(b, names[k], [k](core::ToolSet& t) -> double& { return t.band.band[k]; }, -1e6, 1e6, 10, 1);
        vec3(b, tr("Axis"), [](core::ToolSet& t) -> glm::dvec3& { return t.band.axis; }, -1, 1);
        auto* m = addGroup("mimda", tr("Importance accumulation (MImDA)"),
                           tr("\u03b3 = 0: plain DVR; 1: important content shines through (thesis \u00a73.2.2)."),
                           [](core::ToolSet& t) -> bool& { return t.mimda.enabled; });
        scalar(m, "\u03b3", [](core::ToolSet& t) -> double& { return t.mimda.gamma; }, 0, 1, 0.05, 2);
    }
    auto* resetButton = new QPushButton(tr("Reset"), this);
    resetButton->setToolTip(tr("Back to the thesis's defaults"));
    connect(resetButton, &QPushButton::clicked, this, &ToolsPanel::reset);
    layout->addWidget(resetButton);
    layout->addStretch(1);
    setTools({});
}

QGroupBox* ToolsPanel::addGroup(const QString& name, const QString& title, const QString& tip, EnabledFlag enabled) {
    auto* g = new QGroupBox(title, this);
    g->setObjectName(name);
    g->setCheckable(true);
    g->setChecked(false);
    g->setToolTip(tip);
    new QFormLayout(g);
    static_cast<QVBoxLayout*>(layout())->addWidget(g);
    groups_.push_back(g);
    connect(g, &QGroupBox::toggled, this, [this] {
        if (!updating_) emit changed();
    });
    show_.push_back([g, enabled](const core::ToolSet& t) { g->setChecked(enabled(const_cast<core::ToolSet&>(t))); });
    read_.push_back([g, enabled](core::ToolSet& t) { enabled(t) = g->isChecked(); });
    return g;
}

QDoubleSpinBox* ToolsPanel::addField(QGroupBox* group, const QString& label, double lo, double hi, double step,
                                     int decimals, const QString& tip) {
    auto* box = new QDoubleSpinBox(group);
    box->setRange(lo, hi);
    box->setSingleStep(step);
    box->setDecimals(decimals);
    box->setKeyboardTracking(false);
    box->setToolTip(tip);
    box->setObjectName(group->objectName() + "." + label);
    static_cast<QFormLayout*>(group->layout())->addRow(label, box);
    connect(box, &QDoubleSpinBox::valueChanged, this, [this] {
        if (!updating_) emit changed();
    });
    return box;
}

void ToolsPanel::setTools(const core::ToolSet& tools) {
    updating_ = true;
    for (auto& s : show_) s(tools);
    updating_ = false;
}

void ToolsPanel::apply(core::ToolSet& tools) const {
    for (const auto& r : read_) r(tools);
}

QGroupBox* ToolsPanel::group(const QString& name) const {
    for (auto* g : groups_)
        if (g->objectName() == name) return g;
    return nullptr;
}

void ToolsPanel::reset() {
    core::ToolSet defaults, current;
    apply(current);
    // Defaults, but keep the on/off state and the placement.
    defaults.focal.enabled = current.focal.enabled;
    defaults.focal.centre = current.focal.centre;
    defaults.context.enabled = current.context.enabled;
    defaults.context.centre = current.context.centre;
    defaults.clip.enabled = current.clip.enabled;
    defaults.band.enabled = current.band.enabled;
    defaults.mimda.enabled = current.mimda.enabled;
    setTools(defaults);
    emit changed();
}

}  // namespace hvx::ui
