#pragma once
// Host side of out-of-core rendering (CHC+RT §5.4): decoded subtrees of a prepared scene kept in an LRU cache
// under a byte budget (--host-cache-mb), read on demand with pread (chs_file.h says why not mmap). The process's
// memory for scene data is then this budget plus the upper hierarchy, however large the file is. A subtree
// larger than the whole budget is still returned (the caller holds it) but not kept.
//
// prefetch() queues subtrees (e.g. those of the invisible front near the view) for a background thread that
// reads them into the store, so a later get() is a hit; the queue is dropped when newer requests arrive.
#include "renderer/outofcore/chs_file.h"

#include <condition_variable>
#include <deque>
#include <list>
#include <memory>
#include <mutex>
#include <thread>
#include <span>
#include <unordered_map>

namespace chcrt::outofcore {

struct SubtreeStoreStats {
    uint64_t hits = 0;
    uint64_t misses = 0;      // reads from the file
    uint64_t evictions = 0;
    uint64_t bytesRead = 0;
    uint64_t residentBytes = 0;
    uint64_t peakResidentBytes = 0;
    uint64_t prefetched = 0; // reads done by the prefetch thread (also counted in misses)
};

class SubtreeStore {
public:
    SubtreeStore(const ChsFile& file, uint64_t budgetBytes);
    ~SubtreeStore(); // stops the prefetch thread
    SubtreeStore(const SubtreeStore&) = delete;
    SubtreeStore& operator=(const SubtreeStore&) = delete;
    // Thread-safe. Throws InputError on a corrupted subtree. `level` >= 1: its LOD proxy (ChsFile::readSubtree),
    // kept under the same budget.
    std::shared_ptr<const SubtreeData> get(uint32_t subtree, uint32_t level = 0);
    const ChsFile& file() const { return file_; }
    uint64_t budgetBytes() const { return budget_; }
    SubtreeStoreStats stats() const;
    // Replaces the prefetch queue (subtrees already resident are skipped). Errors while prefetching are
    // ignored: the later get() reads again and reports them.
    void prefetch(std::span<const uint32_t> subtrees);
    // Blocks until the prefetch queue is empty and no read is in flight (tests, benchmarks).
    void waitForPrefetch();

private:
    struct Entry {
        std::shared_ptr<const SubtreeData> data;
        std::list<uint64_t>::iterator position;
    };
    static uint64_t keyOf(uint32_t subtree, uint32_t level) { return uint64_t(level) << 32 | subtree; }
    const ChsFile& file_;
    uint64_t budget_;
    mutable std::mutex mutex_;
    std::list<uint64_t> lru_; // keys (keyOf), most recently used first
    std::unordered_map<uint64_t, Entry> entries_;
    SubtreeStoreStats stats_;
    std::shared_ptr<const SubtreeData> insert(uint64_t key, std::shared_ptr<const SubtreeData> data, bool prefetched);
    void prefetchLoop();
    std::deque<uint32_t> queue_;
    bool stopping_ = false;
    bool busy_ = false;
    std::condition_variable wake_, idle_;
    std::thread worker_; // started on the first prefetch()
};

} // namespace chcrt::outofcore
