#include "ui/LightFieldPreviewWindow.h"

#include <QHBoxLayout>
#include <QLabel>
#include <QPixmap>
#include <QSlider>
#include <QVBoxLayout>

namespace hvx::ui {

LightFieldPreviewWindow::LightFieldPreviewWindow(QWidget* parent)
    : QWidget(parent, Qt::Window), image_(new QLabel(this)), caption_(new QLabel(this)),
      observer_(new QSlider(Qt::Horizontal, this)) {
    setObjectName("lightFieldPreviewWindow");
    setWindowTitle(tr("Light-field preview"));
    image_->setMinimumSize(320, 200);
    image_->setAlignment(Qt::AlignCenter);
    image_->setStyleSheet("background: black");
    image_->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored);
    caption_->setWordWrap(true);
    observer_->setObjectName("previewObserver");
    observer_->setRange(-100, 100);
    observer_->setToolTip(tr("The observer's horizontal position across the display's field of view"));
    auto* row = new QHBoxLayout;
    row->addWidget(new QLabel(tr("Observer"), this));
    row->addWidget(observer_, 1);
    auto* layout = new QVBoxLayout(this);
    layout->addWidget(image_, 1);
    layout->addLayout(row);
    layout->addWidget(caption_);
    resize(800, 560);
}

void LightFieldPreviewWindow::setImage(const QImage& image, const QString& caption) {
    source_ = image;
    caption_->setText(caption);
    rescale();
}

QImage LightFieldPreviewWindow::shown() const { return image_->pixmap().toImage(); }

void LightFieldPreviewWindow::resizeEvent(QResizeEvent* e) {
    QWidget::resizeEvent(e);
    rescale();
}

void LightFieldPreviewWindow::rescale() {
    if (source_.isNull()) return;
    image_->setPixmap(QPixmap::fromImage(source_).scaled(image_->size(), Qt::KeepAspectRatio, Qt::SmoothTransformation));
}

}  // namespace hvx::ui
