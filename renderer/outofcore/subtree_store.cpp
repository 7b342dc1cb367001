#include "renderer/outofcore/subtree_store.h"

namespace chcrt::outofcore {

std::unique_ptr<SubtreeData> SubtreeBuffers::take(uint32_t nodes, uint32_t triangles) {
    const std::lock_guard lock(mutex_);
    size_t best = spare_.size();
    for (size_t i = 0; i < spare_.size(); ++i) {
        const SubtreeData& d = *spare_[i];
        // A compact file's reads fill the compact parts (the store does not decode them).
        const bool holds = d.compactNodes.capacity() != 0
                               ? d.compactNodes.capacity() >= uint64_t(nodes) + CHCRT_COMPACT_ROOT_TEXELS - 1 &&
                                     d.compactTriangles.capacity() >= triangles
                               : d.nodes.capacity() >= nodes && d.triangles.capacity() >= triangles &&
                                     d.normals.capacity() >= size_t(triangles) * 3;
        if (!holds) continue;
        if (best == spare_.size() || d.bytes() < spare_[best]->bytes()) best = i;
    }
    if (best == spare_.size()) return std::make_unique<SubtreeData>();
    std::unique_ptr<SubtreeData> taken = std::move(spare_[best]);
    spare_.erase(spare_.begin() + std::ptrdiff_t(best));
    return taken;
}

void SubtreeBuffers::giveBack(SubtreeData* data) {
    std::unique_ptr<SubtreeData> owned(data);
    const std::lock_guard lock(mutex_);
    if (spare_.size() < kSpareBuffers) spare_.push_back(std::move(owned));
}

SubtreeStore::SubtreeStore(const ChsFile& file, uint64_t budgetBytes) : file_(file), budget_(budgetBytes) {}

std::shared_ptr<const SubtreeData> SubtreeStore::read(uint32_t subtree, uint32_t level, bool attributes) const {
    uint32_t nodes = 0, triangles = 0;
    if (level == 0 && subtree < file_.subtrees().size()) {
        nodes = file_.subtrees()[subtree].nodeCount;
        triangles = file_.subtrees()[subtree].triangleCount;
    } else if (level != 0) {
        const ChsLodRecord& r = file_.lodRecord(subtree, level); // throws for a level or subtree out of range
        nodes = r.nodeCount;
        triangles = r.triangleCount;
    }
    std::unique_ptr<SubtreeData> data = buffers_->take(nodes, triangles);
    file_.readSubtree(subtree, level, *data, attributes, false); // compact blobs stay compact (SubtreeData::triangle)
    return {data.release(), [buffers = buffers_](const SubtreeData* d) { buffers->giveBack(const_cast<SubtreeData*>(d)); }};
}

SubtreeStore::~SubtreeStore() {
    {
        const std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
}

void SubtreeStore::evictLeastRecent() {
    const uint64_t victim = lru_.back();
    lru_.pop_back();
    const Entry& entry = entries_.at(victim);
    const uint64_t bytes = entry.data->bytes();
    if (entry.prefetchedUnused) {
        stats_.prefetchWastedBytes += bytes;
        unusedPrefetchBytes_ -= bytes;
    }
    stats_.residentBytes -= bytes;
    entries_.erase(victim);
    ++stats_.evictions;
}

bool SubtreeStore::prefetchFits(uint64_t bytes) const {
    if (bytes > budget_) return false;
    uint64_t room = budget_ - stats_.residentBytes;
    // The list is in order of use, so the subtrees a prefetch may evict (used before the previous frame) are a
    // suffix of it: stop at the first one it may not.
    for (auto it = lru_.rbegin(); it != lru_.rend() && room < bytes; ++it) {
        const Entry& entry = entries_.at(*it);
        if (!evictableForPrefetch(entry)) return false;
        room += entry.data->bytes();
    }
    return room >= bytes;
}

std::shared_ptr<const SubtreeData> SubtreeStore::insert(uint64_t key, std::shared_ptr<const SubtreeData> data,
                                                        bool prefetched) {
    const uint64_t bytes = data->bytes();
    ++stats_.misses;
    if (prefetched) ++stats_.prefetched;
    stats_.bytesRead += data->readBytes();
    const auto existing = entries_.find(key);
    if (existing != entries_.end()) {
        if (existing->second.data->attributes || !data->attributes) return existing->second.data; // a concurrent read won
        // The entry was read for the GPU alone; this read has the attributes too and replaces it.
        if (existing->second.prefetchedUnused) unusedPrefetchBytes_ -= existing->second.data->bytes();
        stats_.residentBytes -= existing->second.data->bytes();
        lru_.erase(existing->second.position);
        entries_.erase(existing);
    }
    if (bytes > budget_ || (prefetched && !prefetchFits(bytes))) {
        // Not kept: larger than the budget, or a prefetch whose room meanwhile went to the frame's own reads.
        if (prefetched) stats_.prefetchWastedBytes += bytes;
        return data;
    }
    while (stats_.residentBytes + bytes > budget_ && !lru_.empty()) evictLeastRecent();
    lru_.push_front(key);
    entries_[key] = {data, lru_.begin(), frame_, prefetched};
    if (prefetched) unusedPrefetchBytes_ += bytes;
    stats_.residentBytes += bytes;
    stats_.peakResidentBytes = std::max(stats_.peakResidentBytes, stats_.residentBytes);
    return data;
}

std::shared_ptr<const SubtreeData> SubtreeStore::get(uint32_t subtree, uint32_t level, bool attributes) {
    const uint64_t key = keyOf(subtree, level);
    {
        std::unique_lock lock(mutex_);
        // The prefetch thread is reading it (prefetches read level 0): wait rather than read it a second time.
        readDone_.wait(lock, [&] { return level != 0 || inFlight_ != subtree; });
        const auto it = entries_.find(key);
        // An entry read for the GPU alone lacks the vertex attributes: read it again with them.
        if (it != entries_.end() && (!attributes || it->second.data->attributes)) {
            Entry& entry = it->second;
            ++stats_.hits;
            if (entry.prefetchedUnused) {
                ++stats_.prefetchHits;
                entry.prefetchedUnused = false;
                unusedPrefetchBytes_ -= entry.data->bytes();
            }
            entry.usedFrame = frame_;
            lru_.splice(lru_.begin(), lru_, entry.position);
            return entry.data;
        }
    }
    // Read outside the lock (pread is thread-safe); a concurrent miss on the same subtree reads it twice, and
    // the first insert wins.
    std::shared_ptr<const SubtreeData> data = read(subtree, level, attributes);
    const std::lock_guard lock(mutex_);
    return insert(key, std::move(data), false);
}

void SubtreeStore::prefetch(std::span<const uint32_t> subtrees, uint64_t maxBytes) {
    {
        const std::lock_guard lock(mutex_);
        queue_.clear();
        // Earlier guesses that no get() has used yet count against this list's bytes: while a frame's worth of them
        // waits unused, nothing more is read (the near path of the 140M city: guesses never used, read every frame
        // on the CPU the frames need, until the store was full).
        const uint64_t allowed = maxBytes > unusedPrefetchBytes_ ? maxBytes - unusedPrefetchBytes_ : 0;
        uint64_t queuedBytes = 0;
        for (uint32_t s : subtrees) {
            if (s >= file_.subtrees().size() || s == inFlight_ || entries_.count(keyOf(s, 0)) != 0) continue;
            const uint64_t bytes = file_.subtrees()[s].bytes;
            if (bytes > allowed - queuedBytes) break; // nearest first: the rest waits for a later list
            queuedBytes += bytes;
            queue_.push_back(s);
        }
        if (!worker_.joinable()) worker_ = std::thread([this] { prefetchLoop(); });
    }
    wake_.notify_all();
}

void SubtreeStore::waitForPrefetch() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [&] { return queue_.empty() && !busy_; });
}

void SubtreeStore::advanceFrame() {
    const std::lock_guard lock(mutex_);
    ++frame_;
}

bool SubtreeStore::contains(uint32_t subtree) const {
    const std::lock_guard lock(mutex_);
    return entries_.count(keyOf(subtree, 0)) != 0;
}

bool SubtreeStore::holdsAttributes(uint32_t subtree, uint32_t level) const {
    const std::lock_guard lock(mutex_);
    const auto it = entries_.find(keyOf(subtree, level));
    return it != entries_.end() && it->second.data->attributes;
}

void SubtreeStore::prefetchLoop() {
    std::unique_lock lock(mutex_);
    for (;;) {
        if (queue_.empty()) idle_.notify_all();
        wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (stopping_) return;
        const uint32_t subtree = queue_.front();
        queue_.pop_front();
        if (entries_.count(keyOf(subtree, 0)) != 0) continue;
        // The record's size is the decoded size to within the blob's padding: checked before reading, so that a
        // prefetch that could not be kept costs no read.
        if (!prefetchFits(file_.subtrees()[subtree].bytes)) {
            ++stats_.prefetchSkipped;
            continue;
        }
        busy_ = true;
        inFlight_ = subtree;
        lock.unlock();
        std::shared_ptr<const SubtreeData> data;
        try {
            data = read(subtree, 0, true); // whole: a prefetched subtree serves uploads and the primary resolve
        } catch (const std::exception&) {
            // Reported by the get() that needs it.
        }
        lock.lock();
        if (data) insert(keyOf(subtree, 0), std::move(data), true);
        inFlight_ = kNone;
        busy_ = false;
        readDone_.notify_all();
    }
}

SubtreeStoreStats SubtreeStore::stats() const {
    const std::lock_guard lock(mutex_);
    return stats_;
}

} // namespace chcrt::outofcore
