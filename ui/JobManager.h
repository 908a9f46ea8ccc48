#pragma once
#include <QObject>
#include <QString>
#include <QTimer>

#include <functional>
#include <deque>
#include <map>
#include <mutex>
#include <memory>

#include "core/base/JobContext.h"

namespace hvx::ui {

/// Runs background jobs (import, build, retrieve) on worker threads and reports them on the
/// GUI thread: progress (fraction, ETA, stage), completion and errors. Each job gets a
/// core::JobContext whose observer posts to the GUI thread (DESIGN.md decision 6: the
/// post-to-main hook); cancel() asks the job to stop at its next check.
///
/// Workers never call into Qt: what they report goes into a mailbox (a std::mutex and a queue)
/// that a timer on the GUI thread empties, in order, so every hand-over between threads is one
/// that ThreadSanitizer sees, and a job's own posts arrive before its end.
///
/// Threading: create, start and cancel on the GUI thread; post() from any thread; signals and
/// posted functions run on the GUI thread.
class JobManager : public QObject {
    Q_OBJECT
public:
    /// The work of a job: runs on a worker thread; throws core::Error to fail and
    /// core::Cancelled when cancelled. Its return value is the result message shown when done.
    using Work = std::function<QString(core::JobContext&)>;
    /// Called on the GUI thread when the job ends well (with the work's message).
    using Done = std::function<void(const QString&)>;

    explicit JobManager(QObject* parent = nullptr);
    ~JobManager() override;

    /// Starts a job; returns its id.
    int start(const QString& title, Work work, Done done = {});
    /// Runs `work` here, on the GUI thread, now (work that needs this thread's OpenGL context, as
    /// a light-field frame), shown in the Jobs panel as any job: its progress reports are shown
    /// as they come (the window repaints; user input waits until it ends, but for the Jobs
    /// panel's Cancel buttons, so that cancel() reaches it) and it ends "done", "failed" or
    /// "cancelled" like the others. Returns the work's message, or throws what it threw.
    QString runHere(const QString& title, const Work& work);
    /// Asks a job to stop.
    void cancel(int id);
    /// Jobs still running.
    int runningCount() const { return int(jobs_.size()); }
    /// Blocks (processing events) until no job runs or `timeoutMs` passes; true when idle (tests, quit).
    bool waitIdle(int timeoutMs);
    /// Runs `onGuiThread` on the GUI thread soon (from a job: results as they arrive). Dropped
    /// when the manager is destroyed first.
    void post(std::function<void()> onGuiThread);

signals:
    void started(int id, const QString& title);
    void progressed(int id, double fraction, double etaSeconds, const QString& stage);
    /// state: "done", "failed" or "cancelled"; message: the result or the error in plain words.
    void finished(int id, const QString& state, const QString& message);

private:
    struct Job;
    struct Mailbox;
    void drain();
    std::map<int, std::shared_ptr<Job>> jobs_;
    std::shared_ptr<Mailbox> mailbox_;
    QTimer* drainTimer_ = nullptr;
    int nextId_ = 1;
    core::JobContext* here_ = nullptr;  // the job runHere() runs, while it runs
    int hereId_ = -1;
};

}  // namespace hvx::ui
