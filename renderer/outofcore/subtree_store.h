#pragma once
// Host side of out-of-core rendering (CHC+RT §5.4): decoded subtrees of a prepared scene kept in an LRU cache
// under a byte budget (--host-cache-mb), read on demand with pread (chs_file.h says why not mmap). The process's
// memory for scene data is then this budget plus the upper hierarchy, however large the file is. A subtree
// larger than the whole budget is still returned (the caller holds it) but not kept.
//
// prefetch() queues subtrees (those a later frame is likely to need: culling/outofcore/subtree_prefetch.h) for a
// background thread that reads them into the store, so a later get() is a hit; the queue is dropped when newer
// requests arrive. A prefetch is a guess, so it yields to the frames' own needs: it never evicts a subtree used
// in the current or the previous frame (advanceFrame() marks frames) and is skipped instead, while a get() may
// evict anything, prefetched subtrees included. Nor does it evict an earlier guess that no get() has used yet: where
// the guesses outnumber the store (the 140M city's near path: the next frames' frustums hold more subtrees than 2
// GiB, most of them hidden), each frame's prefetch evicted the last frame's and read 256 MB more, used by nothing,
// on the CPU the frame needs (316 against 249 ms per frame); now the store fills with guesses once and prefetching
// waits until get()s have made room. Nor does it read more while guesses of a frame's prefetch bytes (prefetch()'s
// maxBytes) wait unused: with a compact file the 2 GiB store holds far more of those guesses, and reading them (256 MB
// per frame, none ever used) made the near path's frames 304 instead of 175 ms. It never takes the store over its budget.
#include "renderer/outofcore/chs_file.h"

#include <condition_variable>
#include <deque>
#include <limits>
#include <list>
#include <memory>
#include <mutex>
#include <thread>
#include <span>
#include <unordered_map>

namespace chcrt::outofcore {

// The buffers of subtrees that left the store and every other holder, kept for the next reads: a read into them
// allocates nothing and touches no fresh page. Without them an exact far frame of the 140M city, whose blobs are
// read again and again through a store smaller than the view needs, spent a tenth of its time in the kernel
// clearing the pages of new buffers (docs/outofcore.md, "Reading subtrees"). Thread-safe; holds at most
// kSpareBuffers subtrees' buffers, outside the store's budget.
class SubtreeBuffers {
public:
    static constexpr size_t kSpareBuffers = 4;
    // The spare with the least capacity that holds `nodes` and `triangles`, else a new one.
    std::unique_ptr<SubtreeData> take(uint32_t nodes, uint32_t triangles);
    void giveBack(SubtreeData* data); // owns `data` from now on

private:
    std::mutex mutex_;
    std::vector<std::unique_ptr<SubtreeData>> spare_;
};

struct SubtreeStoreStats {
    uint64_t hits = 0;
    uint64_t misses = 0;      // reads from the file
    uint64_t evictions = 0;
    uint64_t bytesRead = 0;
    uint64_t residentBytes = 0;
    uint64_t peakResidentBytes = 0;
    uint64_t prefetched = 0; // reads done by the prefetch thread (also counted in misses)
    // get()s answered by a subtree that was in the store only because the prefetch thread had read it (each
    // prefetched subtree counts once, at its first use; a get() that waited for the read in flight counts too).
    uint64_t prefetchHits = 0;
    // Decoded bytes of prefetched subtrees that left the store before any get() used them, or that were read but
    // not kept (room could not be made by then without evicting a recently used subtree).
    uint64_t prefetchWastedBytes = 0;
    // Queued prefetches not read: no room without evicting a subtree used in the current or the previous frame.
    uint64_t prefetchSkipped = 0;
};

class SubtreeStore {
public:
    static constexpr uint64_t kNoByteLimit = std::numeric_limits<uint64_t>::max();

    SubtreeStore(const ChsFile& file, uint64_t budgetBytes);
    ~SubtreeStore(); // stops the prefetch thread
    SubtreeStore(const SubtreeStore&) = delete;
    SubtreeStore& operator=(const SubtreeStore&) = delete;
    // Thread-safe. Throws InputError on a corrupted subtree. `level` >= 1: its LOD proxy (ChsFile::readSubtree),
    // kept under the same budget. Prefetches read subtrees (level 0) only.
    // `attributes` false: the caller needs nodes and triangles only (a GPU upload), and a blob already verified is
    // read without its vertex normals and texture coordinates (a third of a city subtree's bytes).
    std::shared_ptr<const SubtreeData> get(uint32_t subtree, uint32_t level = 0, bool attributes = true);
    const ChsFile& file() const { return file_; }
    uint64_t budgetBytes() const { return budget_; }
    SubtreeStoreStats stats() const;
    // Replaces the prefetch queue with `subtrees` in their order, leaving out those already resident and stopping
    // once the queued ones' sizes (the file's records) would pass `maxBytes`. Errors while prefetching are
    // ignored: the later get() reads again and reports them.
    void prefetch(std::span<const uint32_t> subtrees, uint64_t maxBytes = kNoByteLimit);
    // Blocks until the prefetch queue is empty and no read is in flight (tests, benchmarks).
    void waitForPrefetch();
    // A new frame begins: subtrees used from the previous frame on are kept from prefetch evictions.
    void advanceFrame();
    bool contains(uint32_t subtree) const; // the subtree itself (level 0)
    // Whether a get(subtree, level, true) would be answered without a read.
    bool holdsAttributes(uint32_t subtree, uint32_t level) const;

private:
    struct Entry {
        std::shared_ptr<const SubtreeData> data;
        std::list<uint64_t>::iterator position;
        uint64_t usedFrame = 0;        // frame of its last get() (or of its prefetch)
        bool prefetchedUnused = false; // read by the prefetch thread, no get() since
    };
    const ChsFile& file_;
    uint64_t budget_;
    // Shared with the deleters of the subtrees handed out, which may outlive the store.
    std::shared_ptr<SubtreeBuffers> buffers_ = std::make_shared<SubtreeBuffers>();
    std::shared_ptr<const SubtreeData> read(uint32_t subtree, uint32_t level, bool attributes) const; // into recycled buffers
    mutable std::mutex mutex_;
    static uint64_t keyOf(uint32_t subtree, uint32_t level) { return uint64_t(level) << 32 | subtree; }
    std::list<uint64_t> lru_; // keys (keyOf), most recently used first
    std::unordered_map<uint64_t, Entry> entries_;
    SubtreeStoreStats stats_;
    uint64_t frame_ = 1;
    uint64_t unusedPrefetchBytes_ = 0; // resident prefetched subtrees no get() has used yet
    // The store's locked operations (mutex_ held).
    std::shared_ptr<const SubtreeData> insert(uint64_t key, std::shared_ptr<const SubtreeData> data, bool prefetched);
    void evictLeastRecent();
    bool evictableForPrefetch(const Entry& entry) const {
        return entry.usedFrame + 1 < frame_ && !entry.prefetchedUnused;
    }
    bool prefetchFits(uint64_t bytes) const; // room for `bytes` without evicting a recently used subtree
    void prefetchLoop();
    std::deque<uint32_t> queue_;
    static constexpr uint32_t kNone = 0xffffffffu;
    uint32_t inFlight_ = kNone; // the subtree the prefetch thread is reading
    bool stopping_ = false;
    bool busy_ = false;
    std::condition_variable wake_, idle_, readDone_;
    std::thread worker_; // started on the first prefetch()
};

} // namespace chcrt::outofcore
