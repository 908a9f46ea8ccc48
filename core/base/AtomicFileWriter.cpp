#include "core/base/AtomicFileWriter.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

#include "core/base/Error.h"

namespace hvx::core {

AtomicFileWriter::AtomicFileWriter(std::string target) : target_(std::move(target)) {
    // A file over RLIMIT_FSIZE would raise SIGXFSZ and kill us; we want EFBIG and a message.
    std::signal(SIGXFSZ, SIG_IGN);
    // A name no other writer has, in this process or another, created exclusively and without
    // following a link planted under it.
    static std::atomic<unsigned long> counter{0};
    for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
        temp_ = target_ + ".partial-" + std::to_string(::getpid()) + "-" + std::to_string(++counter);
        fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd_ < 0 && errno != EEXIST) break;
    }
    if (fd_ < 0) {
        const int err = errno;
        throw Error(target_ + ": cannot write output (" + std::strerror(err) + ")");
    }
}

AtomicFileWriter::~AtomicFileWriter() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(temp_.c_str());
}

void AtomicFileWriter::fail(const char* what, int err) {
    std::string reason = std::strerror(err);
    if (err == ENOSPC || err == EFBIG || err == EDQUOT) reason = "disk full or file size limit reached: " + reason;
    throw Error(target_ + ": " + what + " failed (" + reason + "); no output was written");
}

void AtomicFileWriter::writeAt(std::uint64_t offset, const void* data, std::size_t size) {
    auto* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::pwrite(fd_, p, size, off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail("write", n < 0 ? errno : ENOSPC);
        p += n;
        offset += std::uint64_t(n);
        size -= std::size_t(n);
    }
}

std::uint64_t AtomicFileWriter::append(const void* data, std::size_t size) {
    const std::uint64_t at = size_;
    writeAt(at, data, size);
    size_ += size;
    // Start writeback of every completed 32 MiB stretch now, so the disk works while we compute
    // and commit()'s fsync has little left to wait for.
    constexpr std::uint64_t kFlushStep = 32u << 20;
    if (size_ - flushed_ >= kFlushStep) {
        ::sync_file_range(fd_, off_t(flushed_), off_t(size_ - flushed_), SYNC_FILE_RANGE_WRITE);
        flushed_ = size_;
    }
    return at;
}

void AtomicFileWriter::commit() {
    if (::fsync(fd_) != 0) fail("flush", errno);
    if (::close(fd_) != 0) {
        fd_ = -1;
        fail("close", errno);
    }
    fd_ = -1;
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) fail("rename", errno);
    committed_ = true;
    // The rename is durable only once the folder is on disk too.
    const auto slash = target_.find_last_of('/');
    const std::string folder = slash == std::string::npos ? "." : (slash == 0 ? "/" : target_.substr(0, slash));
    const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
}

}  // namespace hvx::core
