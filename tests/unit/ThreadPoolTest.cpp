#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "core/base/ThreadPool.h"

using hvx::core::ThreadPool;

TEST(ThreadPool, ParallelForVisitsEveryIndexOnce) {
    ThreadPool pool(3);
    std::vector<std::atomic<int>> hits(1000);
    pool.parallelFor(hits.size(), [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) ++hits[i];
    }, 7);
    for (const auto& h : hits) EXPECT_EQ(h.load(), 1);
}

TEST(ThreadPool, NestedParallelForDoesNotDeadlock) {
    ThreadPool pool(2);
    std::atomic<int> total{0};
    pool.parallelFor(8, [&](std::size_t, std::size_t) {
        pool.parallelFor(100, [&](std::size_t b, std::size_t e) { total += int(e - b); });
    });
    EXPECT_EQ(total.load(), 800);
}

TEST(ThreadPool, FirstExceptionReachesTheCaller) {
    ThreadPool pool(2);
    EXPECT_THROW(pool.parallelFor(50, [](std::size_t b, std::size_t) {
        if (b == 17) throw std::runtime_error("boom");
    }), std::runtime_error);
}
