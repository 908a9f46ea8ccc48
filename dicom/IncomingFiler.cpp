#include "dicom/IncomingFiler.h"

#include <utility>

#include "core/base/Error.h"

namespace hvx::dicom {

IncomingFiler::IncomingFiler(IncomingStore& store, int threads) : store_(store) {
    for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { work(); });
}

IncomingFiler::~IncomingFiler() {
    {
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [this] { return undone_ == 0; });
        stopping_ = true;
    }
    changed_.notify_all();
    for (auto& t : threads_) t.join();
}

void IncomingFiler::submit(std::string temporary, const std::function<void(const DicomInstance&)>& onStored) {
    std::unique_lock lock(mutex_);
    deliverDone(lock, onStored);
    while (undone_ >= kMaxPending) {  // the disk is slower than the network: wait for it
        changed_.wait(lock);
        deliverDone(lock, onStored);
    }
    items_.push_back(Item{std::move(temporary), false, {}, {}});
    ++undone_;
    changed_.notify_all();
}

void IncomingFiler::finish(const std::function<void(const DicomInstance&)>& onStored) {
    std::unique_lock lock(mutex_);
    for (;;) {
        deliverDone(lock, onStored);
        if (undone_ == 0) break;
        changed_.wait(lock);
    }
    if (!firstError_.empty()) throw core::Error(std::exchange(firstError_, std::string()));
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
        changed_.wait(lock, [this] { return stopping_ || next_ < first_ + items_.size(); });
        if (next_ >= first_ + items_.size()) return;  // stopping, nothing left to take
        const std::uint64_t seq = next_++;
        const std::string temporary = items_[std::size_t(seq - first_)].temporary;
        lock.unlock();
        DicomInstance in;
        std::string error;
        try {
            in = store_.finalize(temporary);  // flushes, renames without replacing, flushes the folder
        } catch (const std::exception& e) {
            error = e.what();
        }
        lock.lock();
        // Only delivered (done) items leave the front, and this one is not done yet: still here.
        Item& item = items_[std::size_t(seq - first_)];
        item.instance = std::move(in);
        item.error = std::move(error);
        item.done = true;
        --undone_;
        changed_.notify_all();
    }
}

}  // namespace hvx::dicom
