#include "core/base/ThreadPool.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <utility>

namespace hvx::core {

ThreadPool::ThreadPool(unsigned threads) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    workers_.reserve(threads);
    for (unsigned t = 0; t < threads; ++t) workers_.emplace_back([this] { workerLoop(); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
}

ThreadPool& ThreadPool::shared() {
    static ThreadPool pool;
    return pool;
}

void ThreadPool::submit(std::function<void()> task) {
    {
        std::lock_guard lock(mutex_);
        tasks_.push_back(std::move(task));
    }
    wake_.notify_one();
}

void ThreadPool::workerLoop() {
    for (;;) {
        std::function<void()> task;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stopping_ || !tasks_.empty(); });
            if (tasks_.empty()) return;
            task = std::move(tasks_.front());
            tasks_.pop_front();
        }
        task();
    }
}

namespace {
struct ForState {
    std::atomic<std::size_t> next{0};
    std::size_t chunks = 0;
    std::size_t done = 0;  // guarded by mutex
    std::mutex mutex;
    std::condition_variable finished;
    std::exception_ptr error;
};
}  // namespace

void ThreadPool::parallelFor(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body,
                             std::size_t grain) {
    if (count == 0) return;
    grain = std::max<std::size_t>(1, grain);
    const std::size_t chunks = (count + grain - 1) / grain;
    if (chunks == 1) {
        body(0, count);
        return;
    }
    auto state = std::make_shared<ForState>();
    state->chunks = chunks;
    auto run = [state, &body, count, grain] {
        for (;;) {
            const std::size_t c = state->next.fetch_add(1);
            if (c >= state->chunks) return;
            try {
                body(c * grain, std::min(count, (c + 1) * grain));
            } catch (...) {
                std::lock_guard lock(state->mutex);
                if (!state->error) state->error = std::current_exception();
            }
            std::lock_guard lock(state->mutex);
            if (++state->done == state->chunks) state->finished.notify_all();
        }
    };
    const std::size_t helpers = std::min<std::size_t>(size(), chunks - 1);
    for (std::size_t h = 0; h < helpers; ++h) submit(run);
    run();
    std::exception_ptr error;
    {
        std::unique_lock lock(state->mutex);
        state->finished.wait(lock, [&] { return state->done == state->chunks; });
        // Taken out of the shared state, so the exception is released on this thread only: a
        // helper dropping the state later must not free it while the caller reads its message
        // (ThreadSanitizer saw exactly that; libstdc++'s own reference count is invisible to it).
        error = std::exchange(state->error, nullptr);
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace hvx::core
