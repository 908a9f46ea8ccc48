#pragma once
// A GUI test's answers to the modal dialogs its clicks open.
#include <QApplication>
#include <QObject>
#include <QPointer>
#include <QTimer>
#include <QWidget>

#include <deque>
#include <functional>
#include <utility>

namespace hvx::test {

/// Answers the modal dialogs a click is about to open, one function per dialog in order, as a
/// user would: each runs once a new modal widget is active (polled, since the click that opens
/// it does not return until it closes).
class DialogAnswers : public QObject {
public:
    explicit DialogAnswers(std::deque<std::function<void(QWidget*)>> answers) : answers_(std::move(answers)) {
        timer_.setInterval(30);
        connect(&timer_, &QTimer::timeout, this, [this] {
            QWidget* w = QApplication::activeModalWidget();
            if (!w || w == last_ || answers_.empty()) return;
            last_ = w;
            auto answer = std::move(answers_.front());
            answers_.pop_front();
            answer(w);
        });
        timer_.start();
    }
    bool done() const { return answers_.empty(); }

private:
    std::deque<std::function<void(QWidget*)>> answers_;
    QTimer timer_;
    QPointer<QWidget> last_;
};

}  // namespace hvx::test
