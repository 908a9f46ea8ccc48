#include "app/cli/SignalCancel.h"

#include <csignal>

namespace hvx::app {

namespace {
core::JobContext* g_job = nullptr;
extern "C" void onSignal(int) {
    if (g_job) g_job->cancel();
}
}  // namespace

SignalCancel::SignalCancel(core::JobContext& job) {
    g_job = &job;
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}

SignalCancel::~SignalCancel() {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    g_job = nullptr;
}

}  // namespace hvx::app
