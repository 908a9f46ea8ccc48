#pragma once
#include <cstdint>
#include <string>

namespace hvx::core {

/// Bytes of physical memory this machine has (sysconf), or 4 GiB when that cannot be read: the
/// bound past which a reader or a build that holds data in memory cannot work at all.
std::uint64_t physicalMemoryBytes();

/// A byte count for a sentence, in GiB with one decimal ("17.4 GiB").
std::string gibibytes(double bytes);

}  // namespace hvx::core
