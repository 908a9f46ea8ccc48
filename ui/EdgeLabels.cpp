#include "ui/EdgeLabels.h"

#include <QCoreApplication>

namespace hvx::ui {

void drawEdgeLabels(QPainter& p, const QRect& area, const QStringList& labels, double fontScale) {
    QFont f = p.font();
    f.setPointSizeF(f.pointSizeF() * fontScale);
    f.setBold(true);
    p.setFont(f);
    const Qt::Alignment where[] = {Qt::AlignLeft | Qt::AlignVCenter, Qt::AlignRight | Qt::AlignVCenter,
                                   Qt::AlignTop | Qt::AlignHCenter, Qt::AlignBottom | Qt::AlignHCenter};
    for (int i = 0; i < 4 && i < labels.size(); ++i) {
        // On a dark box: a letter over bright tissue or bone stays readable.
        const QRect used = p.boundingRect(area, int(where[i]), labels[i]);
        p.fillRect(used.adjusted(-2, 0, 2, 0), QColor(0, 0, 0, 150));
        p.setPen(QColor(255, 230, 120));
        p.drawText(area, int(where[i]), labels[i]);
    }
}

QStringList assumedGeometryNotes(const core::VolumeGeometry& g) {
    QStringList notes;
    if (g.spacingAssumed) notes << QCoreApplication::translate("SliceView", "spacing unknown (1 mm assumed)");
    if (g.orientationAssumed) notes << QCoreApplication::translate("SliceView", "orientation unknown (L/R?)");
    return notes;
}

void drawAssumedGeometry(QPainter& p, const QRect& area, const core::VolumeGeometry& g) {
    const QStringList notes = assumedGeometryNotes(g);
    if (notes.isEmpty()) return;
    QFont f = p.font();
    f.setBold(true);
    p.setFont(f);
    p.setPen(QColor(255, 170, 40));
    p.drawText(area, Qt::AlignTop | Qt::AlignRight | Qt::TextWordWrap, notes.join('\n'));
}

}  // namespace hvx::ui
