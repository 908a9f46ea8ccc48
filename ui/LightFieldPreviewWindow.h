#pragma once
#include <QImage>
#include <QWidget>

class QLabel;
class QSlider;

namespace hvx::ui {

/// The light-field preview in a window of its own, resizable, where it can be seen (the dock's
/// copy lies below the fold of a small dock): what an observer sees on the display (or the
/// quilt, or the stereo frame), scaled to the window, with the observer slider beside it.
///
/// Threading: GUI thread only.
class LightFieldPreviewWindow : public QWidget {
    Q_OBJECT
public:
    explicit LightFieldPreviewWindow(QWidget* parent = nullptr);
    void setImage(const QImage& image, const QString& caption);
    /// The observer's horizontal position, -100 to 100 (the panel keeps its own in step).
    QSlider* observer() const { return observer_; }
    /// The image as shown, scaled to the window.
    QImage shown() const;

protected:
    void resizeEvent(QResizeEvent* e) override;

private:
    void rescale();

    QLabel* image_;
    QLabel* caption_;
    QSlider* observer_;
    QImage source_;
};

}  // namespace hvx::ui
