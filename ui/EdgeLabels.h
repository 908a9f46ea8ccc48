#pragma once
#include <QPainter>
#include <QStringList>

namespace hvx::ui {

/// Draws patient-orientation letters at the middle of the left, right, top and bottom edges of
/// `area` (labels in that order), bold, in the viewers' label colour; shared by the 3D view and
/// the slice views.
void drawEdgeLabels(QPainter& painter, const QRect& area, const QStringList& labels, double fontScale = 1.0);

}  // namespace hvx::ui
