#pragma once
// GPU side of out-of-core rendering (CHC+RT §5.4): termination subtrees of a prepared scene are uploaded on
// demand into fixed-size slots of two texture buffers (nodes, triangles; layouts of shaders/shared/bvh_layout.h)
// whose sizes follow from --gpu-cache-mb. Every slot holds the largest subtree of the file, so any subtree fits
// any slot and allocation is a choice of victim: round-robin (the paper's policy) or least recently used.
// Uploads rebase the subtree's local indices by the slot's first node and triangle. The budget is checked
// against the buffers actually allocated, which never grow.
//
// A file of compact subtrees (version 3, renderer/outofcore/compact_subtree.h) is kept as stored: node and triangle
// texels (RGBA32UI) and a third buffer of vertices (RGB32F, CHCRT_UNIT_BVH_VERTICES), about half the bytes per
// subtree, so the same budget holds about twice the subtrees; the tracer's shaders then decode it
// (CHCRT_COMPACT_SUBTREES, compact()). Indices stay local: an upload copies the blob's parts and writes the slot's
// triangle and vertex bases into the root's texel 2 (no pass over the nodes). Slot sizes count node texels (a
// subtree's node count + 2) and vertices too.
//
// Subtree indices are indices into the file's directory (ChsFile::subtrees()).
//
// Level of detail (chcrt-lod, issue #19; renderer/outofcore/lod_proxies.h): with GpuCacheOptions::lodPixels > 0 and a
// file with proxies, a requested subtree is served at the coarsest level whose geometric error projects below
// lodPixels pixels from the view set by setView() (error × focal length / distance from the eye to the subtree's
// box; an eye inside the box gets the subtree itself). Entries are keyed by (subtree, level): the subtree pool
// holds full subtrees, and each proxy level has a pool of its own (proxies are 8-500× smaller, so equal slots for
// both would waste most of the budget) in which proxies are packed at their own sizes (packed_ring.h: one level's
// proxies differ in size by 10× and more). Exact methods run with lodPixels 0: no proxy pool is allocated and no
// proxy is ever served (tested: proxy uploads stay 0).
#include "culling/outofcore/packed_ring.h"
#include "culling/subtree_source.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/outofcore/gpu_cache_slots.h"
#include "renderer/outofcore/subtree_store.h"

#include <optional>
#include <string>
#include <vector>

namespace chcrt::outofcore {

enum class CachePolicy { RoundRobin, Lru };
CachePolicy parseCachePolicy(const std::string& text); // "round-robin" | "lru"; InputError otherwise
const char* toString(CachePolicy policy);

struct GpuCacheOptions {
    uint64_t budgetBytes = 1024ull << 20;
    CachePolicy policy = CachePolicy::Lru;
    // Subtrees uploaded per trace at most (0 = no limit: every trace is complete and exact). The viewer streams
    // with a limit so that a cold cache costs several short frames instead of one long one.
    uint32_t maxUploadsPerTrace = 0;
    // chcrt-lod: serve a subtree's LOD proxy where its error projects below this many pixels; 0 = exact (never).
    float lodPixels = 0.0f;
};

// Share of the budget each proxy level's pool may take (at most what all of that level's proxies need, packed), the
// coarsest level's more: a far view needs it for nearly every subtree. The subtree pool gets the rest (near views
// need it; exact methods have no proxy pools). At 1/8 and 1/4 the 140M city's far path (640×360, 1 GiB; equal slots
// then) uploaded 145-228 proxies per trace, both pools too small for the ~2,800 coarsest and ~250 level-1 proxies a
// view asks for; at 1/6 and 1/3, 41-49 (docs/benchmarks.md, 2026-12-06).
inline constexpr double kLodPoolShare = 1.0 / 6.0;
inline constexpr double kLodCoarsestPoolShare = 1.0 / 3.0;
inline constexpr uint32_t kLodStatLevels = 5; // statistics per level 0 (subtree) ... 4 (kMaxLodLevels)

struct GpuCacheStats {
    uint64_t hits = 0;
    uint64_t misses = 0;    // uploads
    uint64_t evictions = 0; // resident entries replaced by uploads (a proxy's upload may replace several smaller ones)
    uint64_t deferred = 0;  // requests answered kNotResident (all slots pinned by the same acquire)
    uint64_t postponed = 0; // requests answered kNotResident because the per-trace upload limit was reached
    uint64_t uploadedNodeBytes = 0;     // BVH MB transferred (Table 3)
    uint64_t uploadedTriangleBytes = 0; // geometry MB transferred
    uint64_t proxyUploads = 0;       // of misses: LOD proxies (level >= 1)
    uint64_t proxyUploadedBytes = 0; // of the bytes uploaded: LOD proxies' nodes + triangles
    uint64_t requestsPerLevel[kLodStatLevels] = {}; // requests served at each level (0 = the subtree)
    uint64_t uploadsPerLevel[kLodStatLevels] = {};
    uint64_t residentBytes = 0;  // nodes + triangles of the resident subtrees
    uint64_t peakResidentBytes = 0; // the most residentBytes has been (kept by resetCounters)
    uint64_t allocatedBytes = 0; // both texture buffers, as allocated (<= budget)
    // The subtree pool's slots plus the proxy pools' (per proxy level: how many of its proxies the pool holds at
    // their mean size, at most all of them; packed_ring.h).
    uint32_t slots = 0;
    uint32_t proxySlots = 0; // of slots: the proxy pools'
    uint32_t residentSubtrees = 0; // entries of every level
};

class GpuSubtreeCache final : public SubtreeSource {
public:
    // Needs a current GL context. Throws InputError when the budget cannot hold one slot.
    GpuSubtreeCache(SubtreeStore& store, const GpuCacheOptions& options);

    void acquire(std::span<const uint32_t> subtrees, std::span<uint32_t> gpuRoots) override;
    // The limit holds only while the subtree pool has a slot the current trace does not use and no proxy pool had
    // to evict (or could not place) an entry of this trace: once this trace's entries fill a pool, later traces
    // could not do better (the working set exceeds the cache), so the trace completes.
    bool uploadBudgetExhausted() const override {
        return options_.maxUploadsPerTrace != 0 && uploadsThisTrace_ >= options_.maxUploadsPerTrace &&
               slotsUsedThisTrace_ < slotCount() && !proxyPoolFullThisTrace_;
    }
    void beginTrace() { // the per-trace upload limit starts again
        uploadsThisTrace_ = 0;
        slotsUsedThisTrace_ = 0;
        proxyPoolFullThisTrace_ = false;
        traceStartTick_ = tick_;
    }

    // chcrt-lod: the eye and the focal length in pixels (half the image height over tan(fovY / 2)) that levels are
    // chosen for, until the next call. Without it (or lodPixels 0) every subtree is served whole.
    void setView(const glm::vec3& eye, float focalPixels) {
        eye_ = eye;
        focalPixels_ = focalPixels;
        viewSet_ = true;
    }
    // The level a request for `subtree` is served at from the current view (0 = the subtree itself).
    uint32_t levelFor(uint32_t subtree) const;
    bool lodEnabled() const { return options_.lodPixels > 0.0f && store_.file().lodLevels() > 0; }
    // The buffers hold the compact layout (shaders need CHCRT_COMPACT_SUBTREES 1).
    bool compact() const { return compact_; }
    bool compactLayout() const override { return compact_; }
    // Hit hints: the epoch counts the uploads that replaced a resident entry (any pool); proxies share the buffers
    // in slots of other sizes, so a cache serving LOD proxies takes none.
    uint64_t contentEpoch() const override { return replacements_; }
    bool hintsSupported() const override { return !lodEnabled(); }
    uint32_t hintSlotNodes() const override { return pools_[0].slotNodes; }
    void bind() override;

    const GpuCacheStats& stats() const { return stats_; }
    void resetCounters(); // per-frame statistics: zero hits/misses/evictions/uploads, keep residency
    // The subtree pool (full subtrees), at the start of both buffers.
    uint32_t slotCount() const { return uint32_t(pools_[0].slotKey.size()); }
    uint32_t slotNodes() const { return pools_[0].slotNodes; } // node records (compact: texels)
    uint32_t slotTriangles() const { return pools_[0].slotTriangles; }
    uint32_t slotVertices() const { return pools_[0].slotVertices; } // 0 in the full layout
    // The index within its subtree of triangle `bufferIndex` of the subtrees' pool (level 0), UINT32_MAX when the
    // index lies outside that pool. Slots hold a subtree's triangles in file order from their first.
    uint32_t localTriangleOf(uint64_t bufferIndex) const {
        const Pool& pool = pools_[0];
        if (bufferIndex < pool.firstTriangle || pool.slotTriangles == 0) return UINT32_MAX;
        const uint64_t offset = bufferIndex - pool.firstTriangle;
        return offset < uint64_t(pool.slotKey.size()) * pool.slotTriangles ? uint32_t(offset % pool.slotTriangles) : UINT32_MAX;
    }
    // The subtree in a slot of the subtree pool (kNotResident when empty).
    uint32_t slotSubtree(uint32_t slot) const { return pools_[0].slotKey[slot]; }
    // The subtree itself (level 0) is in the cache (prefetch leaves resident ones out).
    bool isResident(uint32_t subtree) const { return pools_[0].slotOf.at(subtree) != kNotResident; }
    // Calls of acquire() so far, and whether `subtree` was asked for (at any level) by one after the first `calls`
    // of them: the prefetch tells a subtree the frame used from one it did not (subtree_prefetch.h).
    uint64_t acquireCount() const { return acquireCount_; }
    bool acquiredAfter(uint32_t subtree, uint64_t calls) const { return lastAcquired_.at(subtree) > calls; }
    GLuint nodeBuffer() const { return nodes_.buffer.id(); }
    GLuint triangleBuffer() const { return triangles_.buffer.id(); }
    GLuint vertexBuffer() const { return vertices_.buffer.id(); } // compact layout only
    GLuint nodeTexture() const { return nodes_.texture.id(); }
    GLuint triangleTexture() const { return triangles_.texture.id(); }

private:
    // One level's entries (0 = subtrees) in a range of each buffer: equal slots for subtrees, packed proxies (`ring`;
    // slot = subtree index) for the levels >= 1.
    struct Pool {
        uint32_t slotNodes = 0, slotTriangles = 0, slotVertices = 0; // equal slots: records of the layout (compact: node texels)
        uint64_t firstNode = 0, firstTriangle = 0, firstVertex = 0;   // where the pool starts in the buffers
        std::optional<PackedRing> ring; // proxy levels: where each resident proxy lies, in units from the pool's start
        std::vector<uint32_t> slotKey;  // subtree in each slot, kNotResident when empty
        std::vector<uint64_t> lastUse;
        std::vector<uint64_t> pinned;   // == acquireCount_: used by the current acquire, not evictable
        std::vector<uint32_t> slotOf;   // per subtree: its slot in this pool, or kNotResident
        uint32_t nextVictim = 0;        // round-robin pointer
        uint64_t nodeBase(uint32_t slot) const { return firstNode + (ring ? ring->offset(slot)[0] : uint64_t(slot) * slotNodes); }
        uint64_t triangleBase(uint32_t slot) const { return firstTriangle + (ring ? ring->offset(slot)[1] : uint64_t(slot) * slotTriangles); }
        uint64_t vertexBase(uint32_t slot) const { return firstVertex + (ring ? ring->offset(slot)[2] : uint64_t(slot) * slotVertices); }
        uint32_t root(uint32_t slot) const { return uint32_t(nodeBase(slot)); }
    };
    uint32_t chooseVictim(Pool& pool); // kNotResident when every slot is pinned
    uint32_t placeProxy(uint32_t level, uint32_t subtree); // its slot, evicting what it is placed over; kNotResident when pinned entries fill the pool
    void upload(uint32_t level, uint32_t subtree, uint32_t slot);
    void evict(uint32_t level, uint32_t slot); // the entry in the slot, if any
    uint64_t entryBytes(uint32_t level, uint32_t subtree) const; // nodes + triangles (+ vertices) on the GPU
    uint32_t nodeUnits(uint32_t nodes) const;                     // node records of a subtree (compact: texels)
    GpuSlotShape shapeOf(const Pool& pool) const;   // of one slot (equal slots)
    GpuSlotShape extentOf(const Pool& pool) const;  // of the whole pool
    PackedRing::Units proxyUnits(uint32_t subtree, uint32_t level) const; // its records and vertices in the buffers
    bool proxyFits(const Pool& pool, uint32_t subtree, uint32_t level) const; // a kept proxy that the pool can hold
    void use(Pool& pool, uint32_t slot);                          // pins and marks it used by this trace

    SubtreeStore& store_;
    GpuCacheOptions options_;
    bool compact_ = false;
    TextureBuffer nodes_, triangles_, vertices_;
    std::vector<Pool> pools_; // [0] subtrees, [l] proxies of level l (empty pools when LOD is off)
    UninitializedVector<BvhNodeGpu> rebased_; // an upload's nodes with slot indices, reused (no allocation per upload)
    std::vector<uint32_t> evictedScratch_;    // placeProxy's evicted entries, reused
    uint64_t acquireCount_ = 0, tick_ = 0;
    std::vector<uint64_t> lastAcquired_; // per subtree: acquireCount_ of the last acquire() that asked for it
    uint64_t replacements_ = 0; // contentEpoch(): never reset (the per-frame evictions are)
    // Per slot of the subtree pool: replacements_ (its low 32 bits) right after the slot's last replacement; uploaded
    // to slotEpochTexture_ by bind() when changed (shared/culling_layout.h, CHCRT_UNIT_CULLING_HINT_SLOTS).
    std::vector<uint32_t> slotEpochs_;
    bool slotEpochsChanged_ = true;
    TextureBuffer slotEpochTexture_;
    uint32_t uploadsThisTrace_ = 0, slotsUsedThisTrace_ = 0; // slots: of the subtree pool
    bool proxyPoolFullThisTrace_ = false;
    uint64_t traceStartTick_ = 0;
    glm::vec3 eye_{0.0f};
    float focalPixels_ = 0.0f;
    bool viewSet_ = false;
    GpuCacheStats stats_;
};

} // namespace chcrt::outofcore
