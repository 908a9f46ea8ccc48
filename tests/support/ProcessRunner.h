#pragma once
#include <string>

namespace hvx::test {

/// Result of running a shell command to completion.
struct ProcessResult {
    int exitCode = -1;    ///< exit status, or 128 + signal
    std::string output;   ///< stdout and stderr together
    long maxRssKiB = 0;   ///< peak resident set size of the child
};

/// Runs `/bin/sh -c command` and waits, collecting output and the child's peak RSS.
ProcessResult runCommand(const std::string& command);

}  // namespace hvx::test
