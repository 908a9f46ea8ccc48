#pragma once
#include <functional>
#include <string>

#include "core/base/Error.h"

namespace hvx::test {

/// The message of the core::Error that `f` throws, or "" when it throws none (any other
/// exception goes on).
inline std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace hvx::test
