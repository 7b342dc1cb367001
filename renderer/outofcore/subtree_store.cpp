#include "renderer/outofcore/subtree_store.h"

namespace chcrt::outofcore {

SubtreeStore::SubtreeStore(const ChsFile& file, uint64_t budgetBytes) : file_(file), budget_(budgetBytes) {}

SubtreeStore::~SubtreeStore() {
    {
        const std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
}

std::shared_ptr<const SubtreeData> SubtreeStore::insert(uint64_t key, std::shared_ptr<const SubtreeData> data,
                                                        bool prefetched) {
    // Called with mutex_ held.
    const uint64_t bytes = data->bytes();
    ++stats_.misses;
    if (prefetched) ++stats_.prefetched;
    const auto subtree = uint32_t(key), level = uint32_t(key >> 32);
    stats_.bytesRead += level == 0 ? file_.subtrees()[subtree].bytes : file_.lodRecord(subtree, level).bytes;
    const auto existing = entries_.find(key);
    if (existing != entries_.end()) return existing->second.data; // a concurrent read won
    if (bytes > budget_) return data;
    while (stats_.residentBytes + bytes > budget_ && !lru_.empty()) {
        const uint64_t victim = lru_.back();
        lru_.pop_back();
        stats_.residentBytes -= entries_.at(victim).data->bytes();
        entries_.erase(victim);
        ++stats_.evictions;
    }
    lru_.push_front(key);
    entries_[key] = {data, lru_.begin()};
    stats_.residentBytes += bytes;
    stats_.peakResidentBytes = std::max(stats_.peakResidentBytes, stats_.residentBytes);
    return data;
}

std::shared_ptr<const SubtreeData> SubtreeStore::get(uint32_t subtree, uint32_t level) {
    const uint64_t key = keyOf(subtree, level);
    {
        const std::lock_guard lock(mutex_);
        const auto it = entries_.find(key);
        if (it != entries_.end()) {
            ++stats_.hits;
            lru_.splice(lru_.begin(), lru_, it->second.position);
            return it->second.data;
        }
    }
    // Read outside the lock (pread is thread-safe); a concurrent miss on the same subtree reads it twice, and
    // the first insert wins.
    auto data = std::make_shared<const SubtreeData>(file_.readSubtree(subtree, level));
    const std::lock_guard lock(mutex_);
    return insert(key, std::move(data), false);
}

void SubtreeStore::prefetch(std::span<const uint32_t> subtrees) {
    {
        const std::lock_guard lock(mutex_);
        queue_.clear();
        for (uint32_t s : subtrees) {
            if (s < file_.subtrees().size() && entries_.count(keyOf(s, 0)) == 0) queue_.push_back(s);
        }
        if (!worker_.joinable()) worker_ = std::thread([this] { prefetchLoop(); });
    }
    wake_.notify_all();
}

void SubtreeStore::waitForPrefetch() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [&] { return queue_.empty() && !busy_; });
}

void SubtreeStore::prefetchLoop() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (stopping_) return;
        const uint32_t subtree = queue_.front();
        queue_.pop_front();
        if (entries_.count(keyOf(subtree, 0)) != 0) {
            if (queue_.empty()) idle_.notify_all();
            continue;
        }
        busy_ = true;
        lock.unlock();
        std::shared_ptr<const SubtreeData> data;
        try {
            data = std::make_shared<const SubtreeData>(file_.readSubtree(subtree));
        } catch (const std::exception&) {
            // Reported by the get() that needs it.
        }
        lock.lock();
        if (data) insert(keyOf(subtree, 0), std::move(data), true);
        busy_ = false;
        if (queue_.empty()) idle_.notify_all();
    }
}

SubtreeStoreStats SubtreeStore::stats() const {
    const std::lock_guard lock(mutex_);
    return stats_;
}

} // namespace chcrt::outofcore
