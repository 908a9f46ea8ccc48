#include "core/streaming/BrickCache.h"

namespace hvx::core {

std::shared_ptr<const Brick> BrickCache::get(std::uint32_t node) {
    std::lock_guard lock(mutex_);
    auto it = map_.find(node);
    if (it == map_.end()) return nullptr;
    lru_.splice(lru_.begin(), lru_, it->second.lru);
    return it->second.brick;
}

bool BrickCache::contains(std::uint32_t node) const {
    std::lock_guard lock(mutex_);
    return map_.count(node) != 0;
}

void BrickCache::put(std::uint32_t node, std::shared_ptr<const Brick> brick) {
    std::lock_guard lock(mutex_);
    auto it = map_.find(node);
    if (it != map_.end()) {
        bytes_ -= it->second.brick->data.size();
        lru_.erase(it->second.lru);
        map_.erase(it);
    }
    bytes_ += brick->data.size();
    lru_.push_front(node);
    map_[node] = Entry{std::move(brick), lru_.begin()};
    while (bytes_ > budget_ && lru_.size() > 1) {
        const std::uint32_t victim = lru_.back();
        lru_.pop_back();
        auto v = map_.find(victim);
        bytes_ -= v->second.brick->data.size();
        map_.erase(v);
    }
}

std::size_t BrickCache::bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
}

std::size_t BrickCache::count() const {
    std::lock_guard lock(mutex_);
    return map_.size();
}

}  // namespace hvx::core
