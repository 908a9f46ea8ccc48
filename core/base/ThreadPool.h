#pragma once
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hvx::core {

/// A fixed set of worker threads serving a FIFO of tasks. Used for compression, filtering,
/// decoding and I/O. parallelFor lets the calling thread take part, so nested use from inside a
/// task cannot deadlock.
///
/// Threading: submit and parallelFor may be called from any thread.
class ThreadPool {
public:
    /// Starts `threads` workers (0 means one per hardware thread).
    explicit ThreadPool(unsigned threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    /// The process-wide pool, one worker per hardware thread.
    static ThreadPool& shared();
    /// Number of worker threads.
    unsigned size() const { return unsigned(workers_.size()); }
    /// Queues a task; it must not throw.
    void submit(std::function<void()> task);
    /// Runs body(begin, end) over [0, count) in chunks of `grain`, on the workers and the caller.
    /// Returns when every chunk is done; rethrows the first exception a chunk threw.
    void parallelFor(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body,
                     std::size_t grain = 1);

private:
    void workerLoop();

    std::vector<std::thread> workers_;
    std::deque<std::function<void()>> tasks_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
};

}  // namespace hvx::core
