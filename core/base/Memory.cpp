#include "core/base/Memory.h"

#include <unistd.h>

#include <cstdio>

namespace hvx::core {

std::uint64_t physicalMemoryBytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) : std::uint64_t(4) << 30;
}

std::string gibibytes(double bytes) {
    char text[48];
    std::snprintf(text, sizeof text, "%.1f GiB", bytes / double(std::uint64_t(1) << 30));
    return text;
}

}  // namespace hvx::core
