#include "ui/TransferFunctionEditor.h"

#include <QComboBox>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QPushButton>
#include <QVBoxLayout>

#include "core/base/Error.h"
#include "ui/GradientOpacityCanvas.h"
#include "ui/RefractionCanvas.h"
#include "ui/TransferFunctionCanvas.h"
#include "ui/TransferFunctionFiles.h"

namespace hvx::ui {

TransferFunctionEditor::TransferFunctionEditor(QWidget* parent)
    : QWidget(parent), canvas_(new TransferFunctionCanvas(this)), gradient_(new GradientOpacityCanvas(this)),
      refraction_(new RefractionCanvas(this)), presets_(new QComboBox(this)) {
    presets_->setObjectName("tfPresets");
    presets_->setToolTip(tr("Built-in transfer functions"));
    for (const auto& n : core::TransferFunction::presetNames()) presets_->addItem(QString::fromStdString(n));
    auto* load = new QPushButton(tr("Load\u2026"), this);
    auto* save = new QPushButton(tr("Save\u2026"), this);
    auto* import = new QPushButton(tr("Import\u2026"), this);
    load->setToolTip(tr("Load a Holovox transfer function (.json)"));
    save->setToolTip(tr("Save this transfer function (.json, physical units)"));
    import->setToolTip(tr("Import a 3D Slicer presets.xml or a ParaView colour map (.json)"));
    auto* row = new QHBoxLayout;
    row->addWidget(presets_, 1);
    row->addWidget(load);
    row->addWidget(save);
    row->addWidget(import);
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(4, 4, 4, 4);
    layout->addLayout(row);
    layout->addWidget(canvas_, 1);
    layout->addWidget(gradient_);
    layout->addWidget(refraction_);
    connect(presets_, &QComboBox::activated, this, [this](int i) { applyPreset(presets_->itemText(i)); });
    connect(canvas_, &TransferFunctionCanvas::edited, this, [this] {
        gradient_->setPoints(canvas_->spec().gradientOpacity);  // window/level scales the gradients too
        refraction_->setPoints(canvas_->spec().refraction);     // and moves the refraction points with the values
        emit changed();
    });
    connect(gradient_, &GradientOpacityCanvas::edited, this, [this] {
        auto s = canvas_->spec();
        s.gradientOpacity = gradient_->points();
        canvas_->setSpec(s);
        emit changed();
    });
    connect(refraction_, &RefractionCanvas::edited, this, [this] {
        auto s = canvas_->spec();
        s.refraction = refraction_->points();
        canvas_->setSpec(s);
        emit changed();
    });
    connect(load, &QPushButton::clicked, this, &TransferFunctionEditor::chooseAndLoad);
    connect(save, &QPushButton::clicked, this, &TransferFunctionEditor::chooseAndSave);
    connect(import, &QPushButton::clicked, this, &TransferFunctionEditor::chooseAndImport);
}

void TransferFunctionEditor::setVolume(double valueMin, double valueMax, double slope, double intercept,
                                       bool hounsfield, const core::VolumeHistogram& histogram) {
    slope_ = slope;
    intercept_ = intercept;
    canvas_->setRange(valueMin, valueMax, slope, intercept);
    canvas_->setHistogram(histogram);
    gradient_->setVolume(slope, histogram);
    refraction_->setVolume(valueMin, valueMax, slope, intercept, histogram);
    const QString preset = hounsfield ? "ct-bone" : "mr-default";
    presets_->setCurrentText(preset);
    applyPreset(preset);
}

void TransferFunctionEditor::applyPreset(const QString& name) {
    try {
        const auto& s = canvas_->spec();
        const double lo = s.opacity.front().value, hi = s.opacity.back().value;
        const auto tf = core::TransferFunction::preset(name.toStdString(), lo, hi, slope_, intercept_, 1.0);
        presets_->setCurrentText(name);
        canvas_->setSpec(core::TransferFunctionSpec::from(tf));
        gradient_->setPoints({});
        refraction_->setPoints({});
        emit changed();
    } catch (const core::Error& e) {
        emit failed(QString::fromStdString(e.what()));
    }
}

const core::TransferFunctionSpec& TransferFunctionEditor::spec() const { return canvas_->spec(); }

void TransferFunctionEditor::setSpec(const core::TransferFunctionSpec& storedUnits) {
    canvas_->setSpec(storedUnits);
    gradient_->setPoints(storedUnits.gradientOpacity);
    refraction_->setPoints(storedUnits.refraction);
    emit changed();
}

void TransferFunctionEditor::showRefractionSetElsewhere(const QString& why,
                                                        const std::vector<core::TransferFunction::RefractionPoint>& drawn) {
    refraction_->showFixed(why, drawn);
}

core::TransferFunction TransferFunctionEditor::transferFunction(double referenceLength) const {
    const auto& s = canvas_->spec();
    return s.build(s.opacity.front().value, s.opacity.back().value, referenceLength);
}

void TransferFunctionEditor::load(const QString& path) {
    setSpec(TransferFunctionFiles::toStored(TransferFunctionFiles::load(path), slope_, intercept_));
}

void TransferFunctionEditor::save(const QString& path) const {
    TransferFunctionFiles::save(TransferFunctionFiles::toPhysical(spec(), slope_, intercept_), path);
}

void TransferFunctionEditor::importSlicer(const QString& path, const QString& name) {
    const auto presets = TransferFunctionFiles::readSlicerPresets(path);
    for (const auto& [n, s] : presets)
        if (name.isEmpty() || n == name) {
            setSpec(TransferFunctionFiles::toStored(s, slope_, intercept_));
            return;
        }
    throw core::Error((path + ": no preset named " + name).toStdString());
}

void TransferFunctionEditor::importParaView(const QString& path) {
    const auto& s = spec();
    setSpec(TransferFunctionFiles::readParaView(path, s.opacity.front().value, s.opacity.back().value, s));
}

void TransferFunctionEditor::chooseAndLoad() {
    const QString path = QFileDialog::getOpenFileName(this, tr("Load transfer function"), {}, tr("Transfer functions (*.json)"));
    if (path.isEmpty()) return;
    try {
        load(path);
    } catch (const core::Error& e) {
        emit failed(QString::fromStdString(e.what()));
    }
}

void TransferFunctionEditor::chooseAndSave() {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save transfer function"), {}, tr("Transfer functions (*.json)"));
    if (path.isEmpty()) return;
    try {
        save(path);
    } catch (const core::Error& e) {
        emit failed(QString::fromStdString(e.what()));
    }
}

void TransferFunctionEditor::chooseAndImport() {
    const QString path = QFileDialog::getOpenFileName(this, tr("Import transfer function"), {},
                                                      tr("3D Slicer presets (*.xml);;ParaView colour maps (*.json)"));
    if (path.isEmpty()) return;
    try {
        if (path.endsWith(".xml", Qt::CaseInsensitive)) {
            QStringList names;
            for (const auto& [n, s] : TransferFunctionFiles::readSlicerPresets(path)) names << n;
            bool ok = false;
            const QString name = QInputDialog::getItem(this, tr("Slicer preset"), tr("Preset:"), names, 0, false, &ok);
            if (ok) importSlicer(path, name);
        } else {
            importParaView(path);
        }
    } catch (const core::Error& e) {
        emit failed(QString::fromStdString(e.what()));
    }
}

}  // namespace hvx::ui
