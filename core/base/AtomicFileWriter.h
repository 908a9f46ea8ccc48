#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace hvx::core {

/// Writes a file under a temporary name beside the target and renames it into place only on
/// commit(), so a crash, a full disk or a cancelled job never leaves a file that looks complete.
/// If destroyed before commit(), the temporary file is removed.
///
/// Threading: one thread at a time.
class AtomicFileWriter {
public:
    /// Creates `<target>.partial-<pid>-<n>` exclusively (O_EXCL, no link followed); throws
    /// core::Error naming the target if it cannot.
    explicit AtomicFileWriter(std::string target);
    ~AtomicFileWriter();
    AtomicFileWriter(const AtomicFileWriter&) = delete;
    AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

    /// Appends bytes at the current end; returns the offset they were written at.
    std::uint64_t append(const void* data, std::size_t size);
    /// Overwrites bytes at an offset already written (e.g. a header).
    void writeAt(std::uint64_t offset, const void* data, std::size_t size);
    /// Bytes written so far.
    std::uint64_t size() const { return size_; }
    /// Flushes to disk and renames onto the target.
    void commit();
    const std::string& target() const { return target_; }
    const std::string& temporaryPath() const { return temp_; }

private:
    [[noreturn]] void fail(const char* what, int err);

    std::string target_;
    std::string temp_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
    std::uint64_t flushed_ = 0;
    bool committed_ = false;
};

}  // namespace hvx::core
