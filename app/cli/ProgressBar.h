#pragma once
#include <string>

#include "core/base/JobContext.h"

namespace hvx::app {

/// A one-line terminal progress bar with percentage and ETA, drawn on stderr when it is a
/// terminal (silent otherwise, so logs stay clean).
class ProgressBar {
public:
    explicit ProgressBar(std::string label);
    ~ProgressBar();
    /// Observer to hand to a core::JobContext.
    core::JobContext::Observer observer();
    void finish();

private:
    void draw(const core::JobProgress& p);
    std::string label_;
    bool enabled_;
    bool drawn_ = false;
};

}  // namespace hvx::app
