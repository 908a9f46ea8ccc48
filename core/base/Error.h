#pragma once
#include <stdexcept>
#include <string>

namespace hvx::core {

/// The one exception type Holovox throws for bad input or failed I/O. Its message is a single
/// sentence for the user that names the thing (file, node, series) and the reason.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Thrown when a job notices its cancellation flag; not an error for the user.
class Cancelled : public std::runtime_error {
public:
    Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace hvx::core
