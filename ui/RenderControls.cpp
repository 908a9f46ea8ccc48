#include "ui/RenderControls.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QActionGroup>
#include <QMenu>
#include <QPushButton>
#include <QSettings>
#include <QToolButton>
#include <QSlider>
#include <QStandardItemModel>

#include <cmath>

namespace hvx::ui {

namespace {
QDoubleSpinBox* spin(double lo, double hi, double step, double value, QWidget* parent) {
    auto* s = new QDoubleSpinBox(parent);
    s->setRange(lo, hi);
    s->setSingleStep(step);
    s->setValue(value);
    s->setKeyboardTracking(false);
    return s;
}
QSlider* slider(int lo, int hi, int value, QWidget* parent) {
    auto* s = new QSlider(Qt::Horizontal, parent);
    s->setRange(lo, hi);
    s->setValue(value);
    return s;
}
}  // namespace

RenderControls::RenderControls(QWidget* parent)
    : QWidget(parent), mode_(new QComboBox(this)), reconstruction_(new QComboBox(this)), shading_(new QCheckBox(tr("Phong shading"), this)),
      subFrames_(new QCheckBox(tr("Moving: rebuild from sub-frames"), this)),
      multilevel_(new QCheckBox(tr("Blend levels where bricks meet"), this)),
      ambient_(spin(0, 1, 0.05, 0.35, this)), diffuse_(spin(0, 1, 0.05, 0.65, this)), specular_(spin(0, 1, 0.05, 0.25, this)),
      shininess_(spin(1, 128, 1, 24, this)), iso_(spin(-1e6, 1e6, 10, 300, this)), boundary_(slider(0, 100, 0, this)),
      viewTransparency_(slider(0, 100, 0, this)), quality_(slider(0, 100, 100, this)), unsharp_(slider(0, 80, 0, this)),
      exaggerated_(slider(0, 100, 0, this)), refraction_(slider(100, 150, 100, this)) {
    refraction_->setObjectName("refraction");
    refraction_->setToolTip(tr("Refraction (thesis \u00a73.2.2): the rays bend by Snell's law where the refraction index "
                               "changes: what the transfer function shows (from 5 % opacity) refracts with the index "
                               "chosen, 1.5 at the right, and air with 1. Left is off. DVR only; not drawn with the illustrative tools, a fused volume "
                               "or split-voxels."));
    unsharp_->setObjectName("normalUnsharp");
    unsharp_->setToolTip(tr("Normal unsharp masking (thesis \u00a73.2.2): each normal pushed away from its neighbourhood's, "
                            "so that fine relief (gyri, vessels, fractures) stands out; left is off, right k = 8"));
    exaggerated_->setObjectName("exaggeratedShading");
    exaggerated_->setToolTip(tr("Exaggerated shading: fine relief lit by a grazing light that follows the coarser surface, "
                                "so it shows at every orientation; left is off"));
    mode_->setObjectName("renderMode");
    mode_->addItems({tr("DVR"), tr("Isosurface"), tr("MIP"), tr("MinIP"), tr("X-ray (average)")});
    mode_->setToolTip(tr("Direct volume rendering, first-hit isosurface, maximum/minimum intensity projection, average"));
    reconstruction_->setObjectName("reconstruction");
    reconstruction_->addItems({tr("Trilinear"), tr("Nearest"), tr("Split-voxels")});
    reconstruction_->setToolTip(
        tr("Between voxels: trilinear interpolation, the nearest voxel, or split-voxels (thesis ch. 4: two values and "
           "the plane between them per cell of 2\u00b3 voxels and more, so that coarse levels keep sharp boundaries "
           "and no colour appears that neither material has; built once in the background; drawn in DVR)"));
    shading_->setChecked(true);
    boundary_->setToolTip(tr("Boundary enhancement: fades homogeneous regions, keeps boundaries"));
    viewTransparency_->setToolTip(tr("View-dependent transparency: boundaries facing you turn transparent, silhouettes stay"));
    quality_->setToolTip(tr("Accuracy: right is one voxel per pixel; left is coarser and faster"));
    quality_->setObjectName("quality");
    iso_->setToolTip(tr("Isovalue in physical units (HU for CT)"));
    auto* form = new QFormLayout(this);
    form->addRow(tr("Mode"), mode_);
    auto* compare = new QPushButton(tr("Compare\u2026"), this);
    compare->setObjectName("compareReconstructions");
    compare->setToolTip(tr("One octree level drawn with trilinear, nearest and split-voxel reconstruction side by side"));
    connect(compare, &QPushButton::clicked, this, &RenderControls::compareRequested);
    // The preset: how images open (a label map opens with split-voxels; each volume keeps its own choice).
    auto* preset = new QToolButton(this);
    preset->setObjectName("reconstructionDefault");
    preset->setText(tr("Default"));
    preset->setToolTip(tr("How images open in 3D from now on (each volume keeps the choice made for it; label maps open with split-voxels)"));
    preset->setPopupMode(QToolButton::InstantPopup);
    auto* menu = new QMenu(preset);
    auto* group = new QActionGroup(menu);
    const QString current = QSettings().value("reconstruction/default", "trilinear").toString();
    for (const auto& [key, text] : {std::pair{"trilinear", tr("Images open trilinear")}, {"nearest", tr("Images open nearest")},
                                    {"split-voxels", tr("Images open with split-voxels")}}) {
        auto* action = menu->addAction(text);
        action->setObjectName(QStringLiteral("reconstructionDefault-%1").arg(QLatin1String(key)));
        action->setCheckable(true);
        action->setChecked(current == QLatin1String(key));
        group->addAction(action);
        connect(action, &QAction::triggered, this, [k = QString::fromLatin1(key)] { QSettings().setValue("reconstruction/default", k); });
    }
    preset->setMenu(menu);
    auto* reconstructionRow = new QHBoxLayout;
    reconstructionRow->addWidget(compare);
    reconstructionRow->addWidget(preset);
    reconstructionRow->addStretch(1);
    form->addRow(tr("Reconstruction"), reconstruction_);
    form->addRow(QString(), reconstructionRow);
    form->addRow(QString(), shading_);
    form->addRow(tr("Ambient"), ambient_);
    form->addRow(tr("Diffuse"), diffuse_);
    form->addRow(tr("Specular"), specular_);
    form->addRow(tr("Shininess"), shininess_);
    form->addRow(tr("Detail (unsharp)"), unsharp_);
    form->addRow(tr("Exaggerated shading"), exaggerated_);
    form->addRow(tr("Refraction"), refraction_);
    form->addRow(tr("Boundary"), boundary_);
    form->addRow(tr("View transparency"), viewTransparency_);
    form->addRow(tr("Isovalue"), iso_);
    form->addRow(tr("Quality"), quality_);
    subFrames_->setObjectName("frameReconstruction");
    subFrames_->setToolTip(tr("While the view moves, draw a quarter of the pixels each frame (a quincunx sub-frame) and "
                              "rebuild the image from the last four, sharp where it stands still (thesis \u00a73.3); off: "
                              "whole frames at a lower resolution. Still views are always drawn whole."));
    remember(subFrames_, "view/frameReconstruction", false);
    form->addRow(QString(), subFrames_);
    multilevel_->setObjectName("multilevel");
    multilevel_->setToolTip(tr("Multilevel sampling (thesis \u00a73.2.2): where a brick meets a coarser one, its samples "
                               "blend with the coarser level towards the shared face, so that no seam shows between levels "
                               "of detail. Trilinear images; a label map, nearest, split-voxels and a fused volume "
                               "sample each brick's own level."));
    remember(multilevel_, "view/multilevel", kMultilevelDefault);
    form->addRow(QString(), multilevel_);
    connect(mode_, &QComboBox::currentIndexChanged, this, [this](int m) {
        iso_->setEnabled(m == 1);
        emit changed();
    });
    iso_->setEnabled(false);
    connect(reconstruction_, &QComboBox::currentIndexChanged, this, &RenderControls::changed);
    connect(shading_, &QCheckBox::toggled, this, &RenderControls::changed);
    for (auto* s : {ambient_, diffuse_, specular_, shininess_, iso_})
        connect(s, &QDoubleSpinBox::valueChanged, this, &RenderControls::changed);
    for (auto* s : {boundary_, viewTransparency_, quality_, unsharp_, exaggerated_})
        connect(s, &QSlider::valueChanged, this, &RenderControls::changed);
    connect(refraction_, &QSlider::valueChanged, this, &RenderControls::refractionChanged);
}

void RenderControls::remember(QCheckBox* box, const QString& key, bool fallback) {
    box->setChecked(QSettings().value(key, fallback).toBool());
    connect(box, &QCheckBox::toggled, this, [this, key](bool on) {
        QSettings().setValue(key, on);
        emit changed();
    });
}

void RenderControls::setVolume(double slope, double intercept, double physicalMin, double physicalMax, bool hounsfield) {
    slope_ = slope;
    intercept_ = intercept;
    iso_->setRange(physicalMin, physicalMax);
    iso_->setValue(hounsfield ? 300.0 : 0.5 * (physicalMin + physicalMax));
}

bool RenderControls::frameReconstruction() const { return subFrames_->isChecked(); }

double RenderControls::refractionIndex() const { return refraction_->value() / 100.0; }

core::RenderSettings RenderControls::settings() const {
    core::RenderSettings s;
    s.mode = core::RenderSettings::Mode(mode_->currentIndex());
    s.shading = shading_->isChecked();
    s.ambient = ambient_->value();
    s.diffuse = diffuse_->value();
    s.specular = specular_->value();
    s.shininess = shininess_->value();
    s.boundary = boundary_->value() / 100.0;
    s.viewTransparency = viewTransparency_->value() / 100.0;
    s.normalUnsharp = unsharp_->value() / 10.0;
    s.exaggeratedShading = exaggerated_->value() / 100.0;
    s.isoValue = (iso_->value() - intercept_) / slope_;
    s.nearest = reconstruction() == Reconstruction::Nearest;
    s.multilevel = multilevel_->isChecked() && reconstruction() == Reconstruction::Trilinear;
    return s;
}

RenderControls::Reconstruction RenderControls::reconstruction() const {
    return Reconstruction(std::max(0, reconstruction_->currentIndex()));
}

void RenderControls::setReconstruction(Reconstruction r, bool labels) {
    const QSignalBlocker b(reconstruction_);
    if (auto* model = qobject_cast<QStandardItemModel*>(reconstruction_->model())) model->item(0)->setEnabled(!labels);
    reconstruction_->setItemText(1, labels ? tr("Nearest (labels)") : tr("Nearest"));
    reconstruction_->setCurrentIndex(int(labels && r == Reconstruction::Trilinear ? Reconstruction::Nearest : r));
}

void RenderControls::setSettings(const core::RenderSettings& s) {
    {
        const QSignalBlocker b(this);
        mode_->setCurrentIndex(int(s.mode));
        shading_->setChecked(s.shading);
        ambient_->setValue(s.ambient);
        diffuse_->setValue(s.diffuse);
        specular_->setValue(s.specular);
        shininess_->setValue(s.shininess);
        boundary_->setValue(int(std::lround(s.boundary * 100)));
        viewTransparency_->setValue(int(std::lround(s.viewTransparency * 100)));
        unsharp_->setValue(int(std::lround(s.normalUnsharp * 10)));
        exaggerated_->setValue(int(std::lround(s.exaggeratedShading * 100)));
    }
    emit changed();
}

double RenderControls::accuracy() const {
    // 100 -> 1 voxel per pixel, 0 -> 8 (three octree levels coarser).
    return std::pow(2.0, 3.0 * (100 - quality_->value()) / 100.0);
}

void RenderControls::setAccuracy(double voxelsPerPixel) {
    quality_->setValue(100 - int(std::lround(std::log2(std::max(1.0, voxelsPerPixel)) / 3.0 * 100)));
}

}  // namespace hvx::ui
