#pragma once
#include <QTimer>
#include <QWidget>

#include <vector>

class QComboBox;
class QLabel;
class QPushButton;
class QSlider;
class QSpinBox;

namespace hvx::ui {

/// The Cine dock: the time points of the open 4D series (echoes, b-values, time points,
/// phases) on a slider, the one shown named by what varies ("time 3"), and play at a chosen
/// rate in a loop or back and forth (bounce). A time point whose octree is still being built
/// is marked and waited for, never skipped silently; one that cannot be shown (another grid)
/// is said and passed over.
///
/// Threading: GUI thread only.
class CinePanel : public QWidget {
    Q_OBJECT
public:
    explicit CinePanel(QWidget* parent = nullptr);
    /// A new series: its time points' names, the one shown, none ready yet but `current`.
    void setTimePoints(const QStringList& names, int current);
    /// No 4D series open: the controls stand aside.
    void clear();
    /// A time point's octree is ready (true), or cannot be shown (false, with the reason).
    void setReady(int index, bool ready, const QString& why = {});
    /// Moves the slider to `index` (as when the user drags it).
    void setCurrent(int index);
    int current() const;
    int count() const { return int(names_.size()); }
    bool isReady(int index) const;
    void setPlaying(bool on);
    bool isPlaying() const { return timer_.isActive(); }
    void setFramesPerSecond(int fps);
    /// Bounce: back and forth between the ends; otherwise a loop.
    void setBounce(bool on);
    /// What the dock says: the time point shown, notes and refusals.
    QString status() const;

signals:
    /// The user (or play) asks for time point `index`.
    void timePointChosen(int index);

private:
    void step();
    void showStatus();

    QStringList names_;
    std::vector<int> state_;  // 0 building, 1 ready, -1 refused
    QStringList refusals_;
    QSlider* slider_;
    QLabel* label_;
    QLabel* note_;
    QPushButton* play_;
    QSpinBox* fps_;
    QComboBox* mode_;
    QTimer timer_;
    int direction_ = 1;
    bool updating_ = false;
};

}  // namespace hvx::ui
