#include "core/base/JobContext.h"

#include <algorithm>

#include "core/base/Error.h"

namespace hvx::core {

void JobContext::throwIfCancelled() const {
    if (cancelled()) throw Cancelled();
}

void JobContext::report(double fraction, const std::string& stage) {
    JobProgress p;
    bool notify = false;
    {
        std::lock_guard lock(mutex_);
        const auto now = Clock::now();
        p.fraction = std::clamp(fraction, 0.0, 1.0);
        p.elapsedSeconds = std::chrono::duration<double>(now - start_).count();
        p.etaSeconds = p.fraction > 0.01 ? p.elapsedSeconds * (1.0 - p.fraction) / p.fraction : -1.0;
        p.stage = stage.empty() ? last_.stage : stage;
        last_ = p;
        if (p.fraction >= 1.0 || p.fraction <= 0.0 || now - lastNotify_ > std::chrono::milliseconds(100)) {
            lastNotify_ = now;
            notify = true;
        }
    }
    if (notify && observer_) observer_(p);
}

JobProgress JobContext::progress() const {
    std::lock_guard lock(mutex_);
    return last_;
}

}  // namespace hvx::core
