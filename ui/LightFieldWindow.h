#pragma once
#include <QImage>
#include <QWidget>

namespace hvx::ui {

/// The second top-level window that drives a multi-view display: it shows the display frame
/// (a quilt, a stereo frame or packed projector images) full screen on a chosen screen, pixel
/// for pixel, as the display's own controller expects.
///
/// Threading: GUI thread only.
class LightFieldWindow : public QWidget {
    Q_OBJECT
public:
    explicit LightFieldWindow(QWidget* parent = nullptr);
    void setFrame(const QImage& frame);
    const QImage& frame() const { return frame_; }
    /// Full screen on screen `index` of QGuiApplication::screens() (clamped).
    void showOnScreen(int index);

protected:
    void paintEvent(QPaintEvent*) override;
    void keyPressEvent(QKeyEvent* e) override;

private:
    QImage frame_;
};

}  // namespace hvx::ui
