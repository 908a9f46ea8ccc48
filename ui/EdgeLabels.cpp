#include "ui/EdgeLabels.h"

namespace hvx::ui {

void drawEdgeLabels(QPainter& p, const QRect& area, const QStringList& labels, double fontScale) {
    QFont f = p.font();
    f.setPointSizeF(f.pointSizeF() * fontScale);
    f.setBold(true);
    p.setFont(f);
    p.setPen(QColor(255, 230, 120));
    const Qt::Alignment where[] = {Qt::AlignLeft | Qt::AlignVCenter, Qt::AlignRight | Qt::AlignVCenter,
                                   Qt::AlignTop | Qt::AlignHCenter, Qt::AlignBottom | Qt::AlignHCenter};
    for (int i = 0; i < 4 && i < labels.size(); ++i) p.drawText(area, int(where[i]), labels[i]);
}

}  // namespace hvx::ui
