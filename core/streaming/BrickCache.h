#pragma once
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "core/octree/Brick.h"

namespace hvx::core {

/// The CPU level of the two-level brick cache: decoded bricks by node id, least recently used
/// evicted first, under a byte budget. The GPU pool is the level above it.
///
/// Threading: all methods are thread-safe (loader threads put, the frame thread gets).
class BrickCache {
public:
    explicit BrickCache(std::size_t byteBudget) : budget_(byteBudget) {}
    /// The brick, marked most recently used; nullptr when absent.
    std::shared_ptr<const Brick> get(std::uint32_t node);
    bool contains(std::uint32_t node) const;
    /// Inserts (or refreshes) a brick, evicting least recently used ones beyond the budget.
    void put(std::uint32_t node, std::shared_ptr<const Brick> brick);
    std::size_t bytes() const;
    std::size_t count() const;
    std::size_t budget() const { return budget_; }

private:
    struct Entry {
        std::shared_ptr<const Brick> brick;
        std::list<std::uint32_t>::iterator lru;
    };
    mutable std::mutex mutex_;
    std::size_t budget_;
    std::size_t bytes_ = 0;
    std::list<std::uint32_t> lru_;  // front = most recent
    std::unordered_map<std::uint32_t, Entry> map_;
};

}  // namespace hvx::core
