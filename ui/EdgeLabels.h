#pragma once
#include <QPainter>
#include <QStringList>

#include "core/volume/VolumeGeometry.h"

namespace hvx::ui {

/// Draws patient-orientation letters at the middle of the left, right, top and bottom edges of
/// `area` (labels in that order), bold, in the viewers' label colour; shared by the 3D view and
/// the slice views.
void drawEdgeLabels(QPainter& painter, const QRect& area, const QStringList& labels, double fontScale = 1.0);

/// What the viewer must not take for a fact about this volume, one line each: "spacing unknown
/// (1 mm assumed)", "orientation unknown (L/R?)"; empty when nothing is assumed.
QStringList assumedGeometryNotes(const core::VolumeGeometry& g);

/// Draws assumedGeometryNotes() at the top right of `area`, in amber.
void drawAssumedGeometry(QPainter& painter, const QRect& area, const core::VolumeGeometry& g);

}  // namespace hvx::ui
