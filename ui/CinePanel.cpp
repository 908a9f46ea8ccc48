#include "ui/CinePanel.h"

#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QSlider>
#include <QSpinBox>
#include <QVBoxLayout>

#include <algorithm>

namespace hvx::ui {

CinePanel::CinePanel(QWidget* parent) : QWidget(parent) {
    auto* layout = new QVBoxLayout(this);
    label_ = new QLabel(this);
    label_->setWordWrap(true);
    layout->addWidget(label_);
    slider_ = new QSlider(Qt::Horizontal, this);
    slider_->setToolTip(tr("The time point shown (echo, b-value, time, phase)"));
    layout->addWidget(slider_);
    auto* row = new QHBoxLayout;
    play_ = new QPushButton(tr("Play"), this);
    play_->setCheckable(true);
    row->addWidget(play_);
    fps_ = new QSpinBox(this);
    fps_->setRange(1, 60);
    fps_->setValue(5);
    fps_->setSuffix(tr(" frames/s"));
    row->addWidget(fps_);
    mode_ = new QComboBox(this);
    mode_->addItems({tr("Loop"), tr("Bounce")});
    row->addWidget(mode_);
    layout->addLayout(row);
    note_ = new QLabel(this);
    note_->setWordWrap(true);
    note_->setStyleSheet("color: rgb(230, 170, 40)");
    layout->addWidget(note_);
    layout->addStretch();

    connect(slider_, &QSlider::valueChanged, this, [this](int v) {
        showStatus();
        if (!updating_) emit timePointChosen(v);
    });
    connect(play_, &QPushButton::toggled, this, &CinePanel::setPlaying);
    connect(fps_, &QSpinBox::valueChanged, this, [this](int fps) { timer_.setInterval(1000 / std::max(1, fps)); });
    connect(&timer_, &QTimer::timeout, this, &CinePanel::step);
    timer_.setInterval(1000 / fps_->value());
    clear();
}

void CinePanel::clear() {
    setPlaying(false);
    names_.clear();
    state_.clear();
    refusals_.clear();
    updating_ = true;
    slider_->setRange(0, 0);
    updating_ = false;
    for (QWidget* w : std::initializer_list<QWidget*>{slider_, play_, fps_, mode_}) w->setEnabled(false);
    label_->setText(tr("Open a volume of a 4D series (echoes, b-values, time points) to play it here."));
    note_->clear();
}

void CinePanel::setTimePoints(const QStringList& names, int current) {
    clear();
    names_ = names;
    state_.assign(std::size_t(names.size()), 0);
    if (current >= 0 && current < names.size()) state_[std::size_t(current)] = 1;
    updating_ = true;
    slider_->setRange(0, std::max(0, int(names.size()) - 1));
    slider_->setValue(current);
    updating_ = false;
    for (QWidget* w : std::initializer_list<QWidget*>{slider_, play_, fps_, mode_}) w->setEnabled(names.size() > 1);
    showStatus();
}

void CinePanel::setReady(int index, bool ready, const QString& why) {
    if (index < 0 || index >= count()) return;
    state_[std::size_t(index)] = ready ? 1 : -1;
    if (!ready) refusals_ << tr("%1 is not shown: %2").arg(names_[index], why);
    showStatus();
}

void CinePanel::setCurrent(int index) { slider_->setValue(index); }

int CinePanel::current() const { return slider_->value(); }

bool CinePanel::isReady(int index) const { return index >= 0 && index < count() && state_[std::size_t(index)] == 1; }

void CinePanel::setPlaying(bool on) {
    on = on && count() > 1;
    if (on) timer_.start();
    else timer_.stop();
    if (play_->isChecked() != on) play_->setChecked(on);
    play_->setText(on ? tr("Pause") : tr("Play"));
}

void CinePanel::setFramesPerSecond(int fps) { fps_->setValue(fps); }

void CinePanel::setBounce(bool on) { mode_->setCurrentIndex(on ? 1 : 0); }

void CinePanel::step() {
    const int n = count();
    if (n < 2) return;
    // The next time point that can be shown; one still building is waited for (the frame
    // stays), one refused is passed over.
    int next = current();
    for (int tries = 0; tries < n; ++tries) {
        if (mode_->currentIndex() == 1) {  // bounce
            if (next + direction_ < 0 || next + direction_ >= n) direction_ = -direction_;
            next += direction_;
        } else {
            next = (next + 1) % n;
        }
        const int s = state_[std::size_t(next)];
        if (s == 1) break;
        if (s == 0) {
            note_->setText(tr("Waiting for %1: its octree is being built.").arg(names_[next]));
            return;
        }
    }
    if (state_[std::size_t(next)] == 1 && next != current()) setCurrent(next);
}

void CinePanel::showStatus() {
    if (names_.isEmpty()) return;
    const int i = current();
    int ready = 0;
    for (const int s : state_) ready += s == 1 ? 1 : 0;
    label_->setText(tr("%1 of %2: %3").arg(i + 1).arg(names_.size()).arg(names_[i]) +
                    (ready < names_.size() ? tr(" \u2022 %1 of %2 time points ready").arg(ready).arg(names_.size()) : QString()));
    note_->setText(refusals_.join("\n"));
}

QString CinePanel::status() const { return label_->text() + (note_->text().isEmpty() ? QString() : "\n" + note_->text()); }

}  // namespace hvx::ui
