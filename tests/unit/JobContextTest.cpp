#include <gtest/gtest.h>

#include <thread>

#include "core/base/Error.h"
#include "core/base/JobContext.h"

using namespace hvx::core;

TEST(JobContext, ReportsProgressWithEtaAndAlwaysTheEnds) {
    std::vector<double> seen;
    JobContext job([&](const JobProgress& p) { seen.push_back(p.fraction); });
    job.report(0.0, "start");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    job.report(0.5);
    job.report(1.0);
    ASSERT_GE(seen.size(), 2u);
    EXPECT_EQ(seen.front(), 0.0);
    EXPECT_EQ(seen.back(), 1.0);
    const auto p = job.progress();
    EXPECT_EQ(p.stage, "start");
    EXPECT_GT(p.elapsedSeconds, 0.0);
    EXPECT_EQ(p.etaSeconds, 0.0);
}

TEST(JobContext, CancelIsSeenFromAnotherThread) {
    JobContext job;
    EXPECT_NO_THROW(job.throwIfCancelled());
    std::thread([&] { job.cancel(); }).join();
    EXPECT_TRUE(job.cancelled());
    EXPECT_THROW(job.throwIfCancelled(), Cancelled);
}
