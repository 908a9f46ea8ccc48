#include "dicom/IncomingFiler.h"

#include <chrono>
#include <set>
#include <utility>

#include "core/base/Error.h"

namespace hvx::dicom {

IncomingFiler::IncomingFiler(IncomingStore& store, int threads) : store_(store) {
    for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { work(); });
}

IncomingFiler::~IncomingFiler() {
    {
        std::unique_lock lock(mutex_);
        ++waiting_;
        changed_.notify_all();
        changed_.wait(lock, [this] { return undone_ == 0; });
        stopping_ = true;
    }
    changed_.notify_all();
    for (auto& t : threads_) t.join();
}

void IncomingFiler::submit(std::string temporary, const std::function<void(const DicomInstance&)>& onStored) {
    std::unique_lock lock(mutex_);
    deliverDone(lock, onStored);
    if (undone_ >= kMaxPending) {  // the disk is slower than the network: wait for it
        ++waiting_;
        changed_.notify_all();
        while (undone_ >= kMaxPending) {
            changed_.wait(lock);
            deliverDone(lock, onStored);
        }
        --waiting_;
    }
    items_.push_back(Item{std::move(temporary), false, {}, {}, {}});
    ++undone_;
    changed_.notify_all();
}

void IncomingFiler::finish(const std::function<void(const DicomInstance&)>& onStored) {
    std::unique_lock lock(mutex_);
    ++waiting_;
    changed_.notify_all();
    for (;;) {
        deliverDone(lock, onStored);
        if (undone_ == 0) break;
        changed_.wait(lock);
    }
    --waiting_;
    if (!firstError_.empty()) throw core::Error(std::exchange(firstError_, std::string()));
}

void IncomingFiler::finishAfterFailure(const std::function<void(const DicomInstance&)>& onStored) {
    try {
        finish(onStored);
    } catch (const std::exception&) {
    }
}

void IncomingFiler::deliverDone(std::unique_lock<std::mutex>& lock,
                                const std::function<void(const DicomInstance&)>& onStored) {
    while (!items_.empty() && items_.front().done) {
        Item item = std::move(items_.front());
        items_.pop_front();
        ++first_;
        if (!item.error.empty()) {
            if (firstError_.empty()) firstError_ = item.error;
            continue;
        }
        lock.unlock();
        if (onStored) onStored(item.instance);
        lock.lock();
    }
}

void IncomingFiler::work() {
    std::unique_lock lock(mutex_);
    for (;;) {
        const auto ready = [this] { return stopping_ || next_ < first_ + items_.size() || flushDue(false); };
        bool woken = true;
        if (unflushed_.empty())  // nothing to flush: sleep until a file comes
            changed_.wait(lock, ready);
        else  // (the worker that renamed last waits here, so a rename never waits longer)
            woken = changed_.wait_for(lock, kFlushDelay, ready);
        if (flushDue(!woken)) {
            flushFolders(lock);
            continue;
        }
        if (next_ >= first_ + items_.size()) {
            if (stopping_) return;
            continue;
        }
        const std::uint64_t seq = next_++;
        const std::string temporary = items_[std::size_t(seq - first_)].temporary;
        lock.unlock();
        IncomingStore::Placed placed;
        std::string error;
        try {
            placed = store_.place(temporary);  // flushes, renames without replacing
        } catch (const std::exception& e) {
            error = e.what();
        }
        lock.lock();
        // Only delivered (done) items leave the front, and this one is not done yet: still here.
        Item& item = items_[std::size_t(seq - first_)];
        item.instance = std::move(placed.instance);
        item.folder = std::move(placed.folder);
        item.error = std::move(error);
        if (item.error.empty())
            unflushed_.push_back(seq);
        else
            markDone(item);
    }
}

bool IncomingFiler::flushDue(bool idle) const {
    // Renames gather into rounds of kFlushRound, unless someone waits for them or no file came
    // for kFlushDelay.
    return !flushing_ && !unflushed_.empty() && (idle || unflushed_.size() >= kFlushRound || waiting_ > 0);
}

void IncomingFiler::flushFolders(std::unique_lock<std::mutex>& lock) {
    // One worker at a time flushes the folders of every instance renamed so far; the others go
    // on filing.
    flushing_ = true;
    const std::vector<std::uint64_t> batch = std::exchange(unflushed_, {});
    std::set<std::string> folders;
    for (const std::uint64_t seq : batch) folders.insert(items_[std::size_t(seq - first_)].folder);
    lock.unlock();
    for (const std::string& folder : folders) IncomingStore::flushFolder(folder);
    lock.lock();
    for (const std::uint64_t seq : batch) markDone(items_[std::size_t(seq - first_)]);
    flushing_ = false;
    changed_.notify_all();
}

void IncomingFiler::markDone(Item& item) {
    item.done = true;
    --undone_;
    changed_.notify_all();
}

}  // namespace hvx::dicom
