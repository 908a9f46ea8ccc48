#include "ui/LightFieldPanel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGuiApplication>
#include <QHBoxLayout>
#include <QLabel>
#include <QPainter>
#include <QPushButton>
#include <QScreen>
#include <QSignalBlocker>
#include <QSlider>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

#include <glm/trigonometric.hpp>

#include "core/base/Error.h"
#include "core/image/LightFieldSimulator.h"
#include "core/image/QuiltLayout.h"
#include "core/image/StereoComposer.h"
#include "ui/ImageConversion.h"
#include "ui/JobManager.h"
#include "ui/LightFieldPreviewWindow.h"
#include "ui/LightFieldWindow.h"
#include "ui/VolumeView.h"

namespace hvx::ui {


LightFieldPanel::LightFieldPanel(VolumeView& view, QWidget* parent)
    : QWidget(parent), view_(view), profiles_(new QComboBox(this)), eta_(new QSlider(Qt::Horizontal, this)),
      zoom_(new QDoubleSpinBox(this)), observer_(new QSlider(Qt::Horizontal, this)), screens_(new QComboBox(this)),
      depth_(new QLabel(this)), previewLabel_(new QLabel(this)), status_(new QLabel(this)),
      follow_(new QCheckBox(tr("Follow the 3D view"), this)) {
    follow_->setToolTip(tr("Re-render with the 3D view: a lowered sampling rate while it moves, full quality when it stops"));
    profiles_->setObjectName("lightFieldProfile");
    for (const auto& n : core::DisplayModel::builtInNames()) profiles_->addItem(QString::fromStdString(n));
    profiles_->setCurrentText("holovizio-96");
    eta_->setRange(0, 100);
    eta_->setValue(100);
    eta_->setToolTip(tr("MCOP blend: 0 = one perspective, 1 = full horizontal parallax (thesis Eq. 5.1)"));
    zoom_->setRange(0.1, 10.0);
    zoom_->setValue(1.0);
    zoom_->setSingleStep(0.1);
    zoom_->setToolTip(tr("Scale of the volume on the display (1 fits it to the screen)"));
    observer_->setRange(-100, 100);
    observer_->setValue(0);
    observer_->setToolTip(tr("Preview: the observer's horizontal position across the display's field of view"));
    for (auto* s : QGuiApplication::screens()) screens_->addItem(s->name());
    previewLabel_->setMinimumSize(200, 150);
    previewLabel_->setAlignment(Qt::AlignCenter);
    previewLabel_->setStyleSheet("background: black");
    status_->setWordWrap(true);
    auto* render = new QPushButton(tr("Render frame"), this);
    render->setObjectName("lightFieldRender");
    auto* output = new QPushButton(tr("Output window"), this);
    output->setToolTip(tr("Show the frame full screen on the chosen screen (the display's input)"));
    auto* form = new QFormLayout;
    form->addRow(tr("Display"), profiles_);
    form->addRow(tr("\u03b7"), eta_);
    form->addRow(tr("Scale"), zoom_);
    form->addRow(tr("Depth range"), depth_);
    form->addRow(tr("Observer"), observer_);
    form->addRow(tr("Screen"), screens_);
    auto* buttons = new QHBoxLayout;
    buttons->addWidget(render);
    buttons->addWidget(output);
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(4, 4, 4, 4);
    layout->addLayout(form);
    layout->addLayout(buttons);
    layout->addWidget(follow_);
    connect(follow_, &QCheckBox::toggled, this, &LightFieldPanel::setFollowView);
    layout->addWidget(previewLabel_, 1);
    layout->addWidget(status_);
    connect(render, &QPushButton::clicked, this, [this] { renderFrame(false, true); });
    connect(output, &QPushButton::clicked, this, &LightFieldPanel::openOutputWindow);
    connect(observer_, &QSlider::valueChanged, this, &LightFieldPanel::updatePreview);
    connect(profiles_, &QComboBox::currentTextChanged, this, &LightFieldPanel::updateDepthRange);
    updateDepthRange();
}

LightFieldPanel::~LightFieldPanel() = default;

void LightFieldPanel::updateDepthRange() {
    try {
        const auto d = core::DisplayModel::load(profiles_->currentText().toStdString());
        // Where the display keeps at least half its on-screen resolution: s(z) <= 2 s(0).
        const double s0 = d.accuracy(0.0);
        const double z = s0 / (d.accuracy(1.0) - s0);
        depth_->setText(tr("\u00b1%1 mm (s(z) \u2264 2\u00b7%2 mm)").arg(z, 0, 'f', 0).arg(s0, 0, 'f', 2));
    } catch (const core::Error& e) {
        depth_->setText(QString::fromStdString(e.what()));
    }
}

void LightFieldPanel::setFollowView(bool follow) {
    if (follow_->isChecked() != follow) follow_->setChecked(follow);
    disconnect(&view_, &VolumeView::frameRendered, this, nullptr);
    if (!follow) return;
    connect(&view_, &VolumeView::frameRendered, this, [this] {
        const bool moving = view_.readouts().resolution < 1.0;
        if (moving || lastInteractive_) renderFrame(moving);  // and once more at full quality when it stops
    });
    renderFrame(false);
}

bool LightFieldPanel::renderFrame(bool interactive, bool asked) {
    lastInteractive_ = interactive;
    try {
        display_ = core::DisplayModel::load(profiles_->currentText().toStdString());
        const auto renderAll = [&](core::JobContext* job) {
            views_ = view_.renderViews(display_, eta_->value() / 100.0, zoom_->value(), 8e6, interactive, job);
        };
        if (asked && jobs_)
            jobs_->runHere(tr("Light-field frame (%1)").arg(profiles_->currentText()), [&](core::JobContext& job) {
                renderAll(&job);
                return tr("%n views", nullptr, int(views_.size()));
            });
        else
            renderAll(nullptr);
        const auto& v = views_.front();
        if (display_.kind == core::DisplayModel::Kind::Lenticular) {
            core::QuiltLayout q{display_.quiltColumns, display_.quiltRows, v.width, v.height, display_.aspect};
            frame_ = toQImage(q.assemble(views_));
        } else if (display_.kind == core::DisplayModel::Kind::Stereo) {
            frame_ = toQImage(core::StereoComposer::compose(display_.layout, views_[0], views_[1]));
        } else {  // projector images side by side in rows of 16
            const int cols = std::min<int>(16, int(views_.size())), rows = (int(views_.size()) + cols - 1) / cols;
            frame_ = QImage(cols * v.width, rows * v.height, QImage::Format_RGB32);
            frame_.fill(Qt::black);
            QPainter p(&frame_);
            for (int i = 0; i < int(views_.size()); ++i) p.drawImage((i % cols) * v.width, (i / cols) * v.height, toQImage(views_[std::size_t(i)]));
        }
        status_->setText(tr("%1: %2 views of %3x%4%5").arg(QString::fromStdString(display_.name)).arg(views_.size()).arg(v.width)
                             .arg(v.height).arg(interactive ? tr(" (interactive: lowered sampling)") : QString()));
        if (asked) {
            if (!previewWindow_) {
                previewWindow_ = std::make_unique<LightFieldPreviewWindow>();
                previewWindow_->observer()->setValue(observer_->value());
                connect(previewWindow_->observer(), &QSlider::valueChanged, observer_, &QSlider::setValue);
                connect(observer_, &QSlider::valueChanged, previewWindow_->observer(), [this](int position) {
                    const QSignalBlocker block(previewWindow_->observer());
                    previewWindow_->observer()->setValue(position);
                });
            }
            previewWindow_->show();
            previewWindow_->raise();
        }
        updatePreview();
        if (window_ && window_->isVisible()) window_->setFrame(frame_);
        return true;
    } catch (const std::exception& e) {  // core::Error, or core::Cancelled from the Jobs panel
        status_->setText(QString::fromStdString(e.what()));
        return false;
    }
}

void LightFieldPanel::updatePreview() {
    if (views_.empty()) return;
    if (display_.kind == core::DisplayModel::Kind::ProjectorArray) {
        // What an observer at the virtual viewer's height and distance sees, moved sideways.
        const double half = display_.observerDistanceMm * std::tan(glm::radians(display_.fieldOfViewDegrees) / 2.0);
        const glm::dvec3 observer(half * observer_->value() / 100.0, display_.observerHeightMm, display_.observerDistanceMm);
        preview_ = toQImage(core::LightFieldSimulator::observe(display_, views_, observer));
    } else {
        preview_ = frame_;
    }
    previewLabel_->setPixmap(QPixmap::fromImage(preview_).scaled(previewLabel_->size(), Qt::KeepAspectRatio, Qt::SmoothTransformation));
    if (previewWindow_) previewWindow_->setImage(preview_, status_->text());
}

void LightFieldPanel::openOutputWindow() {
    if (!window_) window_ = std::make_unique<LightFieldWindow>();
    window_->setFrame(frame_);
    window_->showOnScreen(screens_->currentIndex());
}

}  // namespace hvx::ui
