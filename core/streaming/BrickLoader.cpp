#include "core/streaming/BrickLoader.h"

namespace hvx::core {

BrickLoader::BrickLoader(const OctreeReader& reader, BrickCache& cache, unsigned threads)
    : reader_(reader), cache_(cache) {
    for (unsigned t = 0; t < std::max(1u, threads); ++t) threads_.emplace_back([this] { work(); });
}

BrickLoader::~BrickLoader() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
        queue_.clear();
    }
    wake_.notify_all();
    for (auto& t : threads_) t.join();
}

void BrickLoader::beginFrame() {
    std::lock_guard lock(mutex_);
    ++frame_;
    for (auto it = queue_.begin(); it != queue_.end();) {
        if (it->second.frame + 1 < frame_) {
            it = queue_.erase(it);
            ++dropped_;
        } else {
            ++it;
        }
    }
}

void BrickLoader::request(std::uint32_t node, double priority) {
    if (cache_.contains(node)) return;
    {
        std::lock_guard lock(mutex_);
        if (failed_.count(node) || inFlight_.count(node)) return;
        queue_[node] = Request{priority, frame_};
    }
    wake_.notify_one();
}

void BrickLoader::loadNow(const std::vector<std::uint32_t>& nodes) {
    for (auto n : nodes) {
        if (cache_.contains(n)) continue;
        {
            std::lock_guard lock(mutex_);
            if (failed_.count(n)) continue;
            queue_.erase(n);
        }
        load(n);
    }
}

void BrickLoader::cancelAll() {
    std::lock_guard lock(mutex_);
    dropped_ += queue_.size();
    queue_.clear();
}

void BrickLoader::waitIdle() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return queue_.empty() && busy_ == 0; });
}

std::size_t BrickLoader::queued() const {
    std::lock_guard lock(mutex_);
    return queue_.size();
}

bool BrickLoader::failed(std::uint32_t node) const {
    std::lock_guard lock(mutex_);
    return failed_.count(node) != 0;
}

std::vector<std::string> BrickLoader::errors() const {
    std::lock_guard lock(mutex_);
    return errors_;
}

void BrickLoader::load(std::uint32_t node) {
    try {
        cache_.put(node, std::make_shared<const Brick>(reader_.readBrick(node)));
        ++loaded_;
    } catch (const std::exception& e) {  // not only Error: a worker thread must never end the process
        std::lock_guard lock(mutex_);
        failed_.insert(node);
        if (errors_.size() < 16) errors_.push_back(e.what());
    }
}

void BrickLoader::work() {
    for (;;) {
        std::uint32_t node = 0;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
            if (stopping_) return;
            auto best = queue_.begin();
            for (auto it = queue_.begin(); it != queue_.end(); ++it)
                if (it->second.priority > best->second.priority) best = it;
            node = best->first;
            queue_.erase(best);
            inFlight_.insert(node);
            ++busy_;
        }
        if (!cache_.contains(node)) load(node);
        {
            std::lock_guard lock(mutex_);
            inFlight_.erase(node);
            --busy_;
        }
        idle_.notify_all();
    }
}

}  // namespace hvx::core
