#include "ui/LightFieldWindow.h"

#include <QGuiApplication>
#include <QKeyEvent>
#include <QPainter>
#include <QScreen>

#include <algorithm>

namespace hvx::ui {

LightFieldWindow::LightFieldWindow(QWidget* parent) : QWidget(parent, Qt::Window) {
    setWindowTitle(tr("Holovox \u2014 light-field output"));
    setToolTip(tr("Esc closes the output window"));
}

void LightFieldWindow::setFrame(const QImage& frame) {
    frame_ = frame;
    update();
}

void LightFieldWindow::showOnScreen(int index) {
    const auto screens = QGuiApplication::screens();
    if (screens.isEmpty()) return;
    QScreen* s = screens[std::clamp(index, 0, int(screens.size()) - 1)];
    setScreen(s);
    setGeometry(s->geometry());
    showFullScreen();
}

void LightFieldWindow::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), Qt::black);
    if (frame_.isNull()) return;
    // Pixel for pixel when it fits (displays read exact pixels), else scaled to fit.
    if (frame_.width() <= width() && frame_.height() <= height()) p.drawImage(0, 0, frame_);
    else p.drawImage(QRect(QPoint(0, 0), frame_.size().scaled(size(), Qt::KeepAspectRatio)), frame_);
}

void LightFieldWindow::keyPressEvent(QKeyEvent* e) {
    if (e->key() == Qt::Key_Escape) close();
    else QWidget::keyPressEvent(e);
}

}  // namespace hvx::ui
