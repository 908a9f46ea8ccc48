#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/streaming/BrickCache.h"
#include "core/octree/OctreeReader.h"

namespace hvx::core {

/// Loader threads that read and decompress bricks into the BrickCache, most urgent first.
/// request() never blocks; requests not renewed by the next frame are dropped as stale; a
/// corrupt brick is recorded (never cached, never drawn) and not requested again.
///
/// Threading: request/beginFrame/cancelAll from the frame thread; workers are internal.
class BrickLoader {
public:
    BrickLoader(const OctreeReader& reader, BrickCache& cache, unsigned threads = 2);
    ~BrickLoader();
    BrickLoader(const BrickLoader&) = delete;
    BrickLoader& operator=(const BrickLoader&) = delete;

    /// Starts a frame: requests from before the previous frame become stale.
    void beginFrame();
    /// Asks for a node (higher priority first); ignored when cached, failed or already queued
    /// (then its priority and frame are refreshed).
    void request(std::uint32_t node, double priority);
    /// Loads these nodes on the calling thread (synchronous mode for tests and the CLI).
    void loadNow(const std::vector<std::uint32_t>& nodes);
    /// Drops every queued request.
    void cancelAll();
    /// Blocks until the queue is empty and the workers idle (tests, synchronous rendering).
    void waitIdle();

    std::size_t queued() const;
    std::size_t loadedCount() const { return loaded_.load(); }
    std::size_t droppedCount() const { return dropped_.load(); }
    bool failed(std::uint32_t node) const;
    std::vector<std::string> errors() const;

private:
    struct Request {
        double priority;
        std::uint64_t frame;
    };
    void work();
    void load(std::uint32_t node);

    const OctreeReader& reader_;
    BrickCache& cache_;
    mutable std::mutex mutex_;
    std::condition_variable wake_, idle_;
    std::unordered_map<std::uint32_t, Request> queue_;
    std::unordered_set<std::uint32_t> inFlight_, failed_;
    std::vector<std::string> errors_;
    std::uint64_t frame_ = 0;
    int busy_ = 0;
    bool stopping_ = false;
    std::atomic<std::size_t> loaded_{0}, dropped_{0};
    std::vector<std::thread> threads_;
};

}  // namespace hvx::core
