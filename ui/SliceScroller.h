#pragma once
#include <QWidget>

class QSlider;
class QTimer;
class QToolButton;
class QSpinBox;

namespace hvx::ui {

class SliceView;

/// The bar under a slice view: a slider over its slices (dragging it scrolls the view; the
/// wheel and keys move it), and cine play at a chosen rate, looping from the last slice to the
/// first.
///
/// Threading: GUI thread only.
class SliceScroller : public QWidget {
    Q_OBJECT
public:
    explicit SliceScroller(SliceView* view, QWidget* parent = nullptr);
    /// Starts or stops cine play.
    void setPlaying(bool on);
    bool playing() const;
    /// Slices per second of cine play (1 to 60).
    void setRate(int slicesPerSecond);
    QSlider* slider() const { return slider_; }

public slots:
    /// Follows the view (a new volume, a step, a tilt): range and position.
    void sync();

private:
    SliceView* view_;
    QSlider* slider_;
    QToolButton* play_;
    QSpinBox* rate_;
    QTimer* timer_;
};

}  // namespace hvx::ui
