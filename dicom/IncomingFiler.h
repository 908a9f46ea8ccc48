#pragma once
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "dicom/DicomInstance.h"
#include "dicom/IncomingStore.h"

namespace hvx::dicom {

/// Files completely received temporary files into an IncomingStore on a few threads of its own,
/// so that a pull from an archive that keeps the originals (WADO-RS, and C-GET, which answers
/// each C-STORE once the instance is written) goes on receiving while earlier
/// instances are flushed to disk: each file is still flushed, renamed and its folder flushed
/// before it is reported (IncomingStore::place, then flushFolder), and the flushes of several
/// files at once share the disk's cache flushes (500 files of 128 KiB: 0.8 s one after the
/// other, 0.2 s four at a time, on this machine's ext4) and, on a file system with a journal,
/// its commits: a WADO-RS of 500 instances onto a journaled ext4 took 0.388 s with four
/// threads, 0.310 s with eight, 0.279 s with sixteen (medians of ten), where on this machine's
/// ext4 without a journal eight were no slower than four and sixteen 20 % slower (the threads'
/// renames contend). One folder flush covers every rename
/// done before it began (a group commit: a WADO-RS of 500 instances from Orthanc on loopback
/// made 79 to 116 folder flushes instead of 500). At most kMaxPending files wait; submit() then
/// waits.
///
/// Threading: submit() and finish() from one thread (the receiving one), which is where
/// onStored runs.
class IncomingFiler {
public:
    explicit IncomingFiler(IncomingStore& store, int threads = 8);
    /// Waits for the files in progress (they are filed; what was not delivered is not reported).
    ~IncomingFiler();
    IncomingFiler(const IncomingFiler&) = delete;
    IncomingFiler& operator=(const IncomingFiler&) = delete;
    /// Queues a temporary file of the store that holds a whole instance, first calling
    /// `onStored` for the instances filed since the last call, in the order submitted (and
    /// waiting while kMaxPending are not filed yet).
    void submit(std::string temporary, const std::function<void(const DicomInstance&)>& onStored);
    /// Waits for every submitted file and delivers them; then throws core::Error with the first
    /// file's error (not DICOM, a conflicting instance), if any.
    void finish(const std::function<void(const DicomInstance&)>& onStored);
    /// After a failed or cancelled transfer: as finish(), the instances already filed reported
    /// all the same, without throwing (the transfer's own error is the one to tell).
    void finishAfterFailure(const std::function<void(const DicomInstance&)>& onStored);
    static constexpr std::size_t kMaxPending = 64;
    /// Renames wait for their folder's flush until there are this many, until the receiving
    /// thread waits for them, or for at most kFlushDelay.
    static constexpr std::size_t kFlushRound = 16;
    static constexpr std::chrono::milliseconds kFlushDelay{10};

private:
    struct Item {
        std::string temporary;
        bool done = false;
        DicomInstance instance;
        std::string folder;  // to flush before the instance is reported
        std::string error;
    };
    void work();
    /// Whether the renamed instances' folders should be flushed now (`idle`: the worker waited
    /// kFlushDelay for nothing); with the lock held.
    bool flushDue(bool idle) const;
    /// Flushes the folders of the renamed instances and marks them done; called with `lock`
    /// held and no other worker flushing, released during the flushes.
    void flushFolders(std::unique_lock<std::mutex>& lock);
    void markDone(Item& item);
    /// Delivers the filed items at the front, in order; called with `lock` held, released
    /// while onStored runs.
    void deliverDone(std::unique_lock<std::mutex>& lock, const std::function<void(const DicomInstance&)>& onStored);
    IncomingStore& store_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<Item> items_;     // submitted, not delivered, in order
    std::uint64_t first_ = 0;    // the sequence number of items_.front()
    std::uint64_t next_ = 0;     // the sequence number of the first item no worker took yet
    std::size_t undone_ = 0;     // submitted and not filed yet
    bool stopping_ = false;
    std::vector<std::uint64_t> unflushed_;  // renamed, their folder not flushed since
    bool flushing_ = false;                 // a worker is flushing folders
    int waiting_ = 0;                       // submit(), finish() or the destructor wait for filed items
    std::string firstError_;
    std::vector<std::thread> threads_;
};

}  // namespace hvx::dicom
