#include "ui/SliceScroller.h"

#include <QHBoxLayout>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QStyle>
#include <QTimer>
#include <QToolButton>

#include <algorithm>

#include "ui/SliceView.h"

namespace hvx::ui {

SliceScroller::SliceScroller(SliceView* view, QWidget* parent)
    : QWidget(parent), view_(view), slider_(new QSlider(Qt::Horizontal, this)), play_(new QToolButton(this)),
      rate_(new QSpinBox(this)), timer_(new QTimer(this)) {
    auto* layout = new QHBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    play_->setCheckable(true);
    play_->setIcon(style()->standardIcon(QStyle::SP_MediaPlay));
    play_->setToolTip(tr("Cine: play through the slices, from the last back to the first"));
    rate_->setRange(1, 60);
    rate_->setValue(10);
    rate_->setSuffix(tr(" /s"));
    rate_->setToolTip(tr("Cine rate: slices per second"));
    slider_->setToolTip(tr("Slice"));
    slider_->setFocusPolicy(Qt::NoFocus);  // the keys stay with the view
    layout->addWidget(play_);
    layout->addWidget(slider_, 1);
    layout->addWidget(rate_);
    connect(slider_, &QSlider::valueChanged, this, [this](int v) { view_->goToSlice(v); });
    connect(play_, &QToolButton::toggled, this, &SliceScroller::setPlaying);
    connect(rate_, &QSpinBox::valueChanged, this, [this](int r) { timer_->setInterval(1000 / r); });
    timer_->setInterval(1000 / rate_->value());
    connect(timer_, &QTimer::timeout, this, [this] {
        const int n = view_->sliceCount();
        if (n <= 1) return setPlaying(false);
        view_->goToSlice((view_->sliceIndex() + 1) % n);
    });
    connect(view, &SliceView::resampled, this, &SliceScroller::sync);
    sync();
}

void SliceScroller::sync() {
    const QSignalBlocker block(slider_);  // following the view must not move it again
    slider_->setRange(0, std::max(0, view_->sliceCount() - 1));
    slider_->setValue(view_->sliceIndex());
    slider_->setEnabled(view_->sliceCount() > 1);
    play_->setEnabled(view_->sliceCount() > 1);
    if (view_->sliceCount() <= 1) setPlaying(false);
}

void SliceScroller::setPlaying(bool on) {
    {
        const QSignalBlocker block(play_);
        play_->setChecked(on);
    }
    play_->setIcon(style()->standardIcon(on ? QStyle::SP_MediaPause : QStyle::SP_MediaPlay));
    if (on) timer_->start();
    else timer_->stop();
}

bool SliceScroller::playing() const { return timer_->isActive(); }

void SliceScroller::setRate(int slicesPerSecond) { rate_->setValue(slicesPerSecond); }

}  // namespace hvx::ui
