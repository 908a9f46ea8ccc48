#pragma once
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <string>

namespace hvx::core {

/// Progress of a job as reported to observers (CLI progress bar, GUI jobs panel).
struct JobProgress {
    double fraction = 0.0;     ///< 0..1
    double elapsedSeconds = 0.0;
    double etaSeconds = -1.0;  ///< < 0 while unknown
    std::string stage;         ///< short text such as "level 0" or "reading"
};

/// The handle a background job receives: it reports progress and polls for cancellation.
/// The observer callback runs on the job's thread; the GUI wraps it in its post-to-main hook.
///
/// Threading: cancel() and cancelled() from any thread; report() from the job's threads.
class JobContext {
public:
    using Observer = std::function<void(const JobProgress&)>;
    explicit JobContext(Observer observer = {}) : observer_(std::move(observer)), start_(Clock::now()) {}
    /// A part of `parent` with progress of its own (a build inside a retrieve): cancelling the
    /// parent cancels it. The parent must outlive it.
    JobContext(const JobContext& parent, Observer observer)
        : observer_(std::move(observer)), start_(Clock::now()), parent_(&parent) {}

    /// Asks the job to stop at its next check.
    void cancel() { cancelled_.store(true); }
    bool cancelled() const { return cancelled_.load() || (parent_ && parent_->cancelled()); }
    /// Throws core::Cancelled if cancel() was called.
    void throwIfCancelled() const;
    /// Publishes progress; calls the observer at most every 100 ms, and always at 0 and 1.
    void report(double fraction, const std::string& stage = {});
    /// The last progress published.
    JobProgress progress() const;

private:
    using Clock = std::chrono::steady_clock;
    Observer observer_;
    Clock::time_point start_;
    Clock::time_point lastNotify_{};
    std::atomic<bool> cancelled_{false};
    const JobContext* parent_ = nullptr;
    mutable std::mutex mutex_;
    JobProgress last_;
};

}  // namespace hvx::core
