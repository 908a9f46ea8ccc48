// The GUI's job manager with jobs that really run at once: some cancelled while they work, one
// failing, the rest finishing; and the manager destroyed (the window closed) while jobs run.
#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QElapsedTimer>

#include <atomic>
#include <chrono>
#include <map>
#include <thread>

#include "core/base/Error.h"
#include "ui/JobManager.h"

using namespace hvx;

namespace {
QCoreApplication& app() {
    static int argc = 1;
    static char name[] = "job_manager_test";
    static char* argv[] = {name, nullptr};
    static QCoreApplication instance(argc, argv);
    return instance;
}

/// Works in small steps until cancelled, or until `steps` are done.
ui::JobManager::Work stepper(int steps, std::atomic<int>& started) {
    return [steps, &started](core::JobContext& job) {
        ++started;
        for (int i = 0; i < steps; ++i) {
            job.throwIfCancelled();
            job.report(double(i) / steps, "step");
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        return QString("finished %1 steps").arg(steps);
    };
}
}  // namespace

TEST(JobManager, CancelledFailedAndFinishedJobsRunningAtOnceEachEndAsTheyShould) {
    app();
    ui::JobManager jobs;
    std::map<int, QString> states;
    std::map<int, int> progressSeen;
    QObject::connect(&jobs, &ui::JobManager::finished,
                     [&](int id, const QString& state, const QString&) { states[id] = state; });
    QObject::connect(&jobs, &ui::JobManager::progressed,
                     [&](int id, double, double, const QString&) { ++progressSeen[id]; });
    std::atomic<int> started{0};
    std::vector<int> endless, quick;
    for (int i = 0; i < 4; ++i) endless.push_back(jobs.start("endless", stepper(1'000'000, started)));
    for (int i = 0; i < 3; ++i) quick.push_back(jobs.start("quick", stepper(20, started)));
    QString doneMessage;
    const int failing = jobs.start(
        "failing", [](core::JobContext&) -> QString { throw core::Error("the disk is full"); });
    const int withDone = jobs.start("with done", stepper(5, started), [&](const QString& m) { doneMessage = m; });

    QElapsedTimer t;
    t.start();
    while (started.load() < 8 && t.elapsed() < 10000) QCoreApplication::processEvents();
    for (int id : endless) jobs.cancel(id);
    ASSERT_TRUE(jobs.waitIdle(20000)) << jobs.runningCount() << " jobs still run";

    for (int id : endless) EXPECT_EQ(states[id], "cancelled") << id;
    for (int id : quick) EXPECT_EQ(states[id], "done") << id;
    EXPECT_EQ(states[failing], "failed");
    EXPECT_EQ(states[withDone], "done");
    EXPECT_EQ(doneMessage, "finished 5 steps");
    EXPECT_GT(progressSeen[quick[0]], 0) << "progress reaches the GUI thread";
    jobs.cancel(endless[0]);  // cancelling a job that has ended is harmless
}

TEST(JobManager, ClosingTheWindowWhileJobsRunCancelsThemAndReturnsPromptly) {
    app();
    std::atomic<int> started{0};
    std::atomic<int> sawCancel{0};
    auto jobs = std::make_unique<ui::JobManager>();
    for (int i = 0; i < 4; ++i)
        jobs->start("transfer", [&](core::JobContext& job) -> QString {
            ++started;
            while (!job.cancelled()) job.report(0.5, "receiving");
            ++sawCancel;
            throw core::Cancelled();
        });
    while (started.load() < 4) std::this_thread::yield();
    const auto before = std::chrono::steady_clock::now();
    jobs.reset();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count();
    EXPECT_EQ(sawCancel.load(), 4);
    EXPECT_LT(seconds, 2.0);
    QCoreApplication::processEvents();  // the jobs' last queued reports find no manager: nothing happens
}
