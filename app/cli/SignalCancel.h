#pragma once
#include "core/base/JobContext.h"

namespace hvx::app {

/// While alive, SIGINT and SIGTERM cancel the given job instead of killing the process, so the
/// job unwinds and removes its temporary files.
class SignalCancel {
public:
    explicit SignalCancel(core::JobContext& job);
    ~SignalCancel();
    SignalCancel(const SignalCancel&) = delete;
    SignalCancel& operator=(const SignalCancel&) = delete;
};

}  // namespace hvx::app
