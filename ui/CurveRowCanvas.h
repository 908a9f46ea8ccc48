#pragma once
#include <QWidget>

#include <cstdint>
#include <vector>

namespace hvx::ui {

/// A row of the transfer-function editor under the opacity curve: a piecewise-linear curve y(x)
/// over a log histogram, x across and y up, constant beyond its end points. Click to add a point,
/// drag to move it, right-click to remove it; with no point the curve is the row's neutral value
/// (drawn dashed: no curve). Every edit emits edited(). A read-only row shows a curve set
/// elsewhere (the reason is its tooltip) and takes no edits. Subclasses give the axes' meaning
/// (GradientOpacityCanvas, RefractionCanvas).
///
/// Threading: GUI thread only.
class CurveRowCanvas : public QWidget {
    Q_OBJECT
public:
    struct Point {
        double x, y;
    };
    explicit CurveRowCanvas(QWidget* parent = nullptr);
    /// x across from xMin to xMax, y up from yMin to yMax; `neutral`: y with no curve.
    void setAxes(double xMin, double xMax, double yMin, double yMax, double neutral);
    /// Counts of bins of `binWidth` from `binOrigin` along x, drawn log-scaled under the curve.
    void setHistogram(std::vector<std::uint64_t> counts, double binOrigin, double binWidth);
    void setCurve(std::vector<Point> points);
    const std::vector<Point>& curve() const { return points_; }
    /// Shows `points` without taking edits (empty `why`: editable again, showing curve()).
    void setReadOnly(const QString& why, std::vector<Point> shown = {});
    bool readOnly() const { return !readOnlyWhy_.isEmpty(); }
    /// Widget position of a point (tests drive the mouse with it).
    QPointF position(double x, double y) const;

signals:
    void edited();

protected:
    /// The labels under the row's left and right ends.
    virtual QString leftLabel() const = 0;
    virtual QString rightLabel() const = 0;
    void paintEvent(QPaintEvent*) override;
    void mousePressEvent(QMouseEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void mouseReleaseEvent(QMouseEvent* e) override;
    double xMin_ = 0.0, xMax_ = 1.0;

private:
    QRectF area() const;
    int hit(const QPointF& p) const;
    Point at(const QPointF& p) const;
    void sortPoints();

    std::vector<Point> points_, shown_;
    std::vector<std::uint64_t> counts_;
    double binOrigin_ = 0.0, binWidth_ = 1.0;
    double yMin_ = 0.0, yMax_ = 1.0, neutral_ = 1.0;
    int dragging_ = -1;
    QString readOnlyWhy_, editTip_;
};

}  // namespace hvx::ui
