#pragma once
#include <QImage>

#include "core/reference/CpuRayCaster.h"

namespace hvx::ui {

/// A rendered frame as a QImage: premultiplied colour over black, encoded to 8-bit sRGB as
/// core::ImageWriter writes PNGs.
QImage toQImage(const core::RenderImage& image);

}  // namespace hvx::ui
