// Parallel build of the Line Spaces of a BVH: work items are (Line Space, face pair), 15 per node, taken in
// order by std::threads from an atomic counter, so only a few nodes' dense scratch arrays are alive at once.
// The thread finishing a node's last face pair packs its bits and candidates; the pools are assembled in node
// order at the end, so the result does not depend on the thread count or scheduling.
#include "linespace/linespace_build.h"

#include "linespace/binary_linespace.h"
#include "linespace/candidate_linespace.h"
#include "linespace/shaft_geometry.h"
#include "linespace/shaft_index.h"
#include "linespace/subtree_query.h"
#include "renderer/core/error.h"

#include <atomic>
#include <bit>
#include <chrono>
#include <cstdio>
#include <memory>
#include <mutex>
#include <thread>

namespace chcrt::ls {

std::string LineSpaceParams::toString() const {
    return "N=" + std::to_string(n) + " D=" + std::to_string(depth) + " T=" + std::to_string(triangleThreshold) +
           (candidates ? " candidates" : " binary");
}

std::string LineSpaceStats::summary() const {
    char line[512];
    const double shafts = static_cast<double>(binaryShafts + candidateShafts);
    std::snprintf(line, sizeof(line),
                  "%u Line Spaces in %.2f s: binary %.1f%% filled (%.2f MB), candidates %.1f%% filled (%.2f MB), "
                  "total %.2f MB, %.3f bytes/shaft",
                  spaceCount, buildSeconds, binaryShafts ? 100.0 * double(binaryFilled) / double(binaryShafts) : 0.0,
                  double(binaryBytes) / 1e6,
                  candidateShafts ? 100.0 * double(candidateFilled) / double(candidateShafts) : 0.0,
                  double(candidateBytes) / 1e6, double(totalBytes()) / 1e6,
                  shafts > 0 ? double(totalBytes()) / shafts : 0.0);
    return line;
}

uint32_t LineSpaces::binaryWordsPerSpace() const { return lsWordCount(params.n, true); }

bool LineSpaces::binaryFilled(uint32_t space, uint32_t symmetricShaft) const {
    const uint32_t word = binaryWords[size_t(space) * binaryWordsPerSpace() + symmetricShaft / 32u];
    return ((word >> (symmetricShaft & 31u)) & 1u) != 0u;
}

std::vector<gpu::LineSpaceNodeGpu> LineSpaces::gpuNodes(const Bvh& bvh) const {
    std::vector<gpu::LineSpaceNodeGpu> records;
    records.reserve(bvhNodes.size());
    for (size_t space = 0; space < bvhNodes.size(); ++space) {
        const BvhNodeGpu& node = bvh.nodes[bvhNodes[space]];
        records.push_back({node.boundsMin, bvhNodes[space], node.boundsMax,
                           static_cast<uint32_t>(space) * binaryWordsPerSpace()});
    }
    return records;
}

std::vector<uint32_t> selectLineSpaceNodes(const Bvh& bvh, uint32_t depth, uint32_t triangleThreshold) {
    const std::vector<TriangleRange> ranges = subtreeTriangleRanges(bvh);
    std::vector<uint32_t> selected;
    std::vector<std::pair<uint32_t, uint32_t>> stack{{0u, 0u}}; // node, depth
    while (!stack.empty()) {
        const auto [node, nodeDepth] = stack.back();
        stack.pop_back();
        if (nodeDepth >= depth || ranges[node].count < triangleThreshold || bvh.isLeaf(node)) {
            selected.push_back(node);
            continue;
        }
        const uint32_t left = bvh.nodes[node].leftFirst;
        stack.push_back({left + 1, nodeDepth + 1});
        stack.push_back({left, nodeDepth + 1});
    }
    return selected;
}

namespace {

// Dense scratch of one Line Space while its face pairs are being built.
struct SpaceScratch {
    std::vector<uint8_t> binary;      // 15 N^4
    std::vector<uint32_t> candidates; // 30 N^4, kEmptyShaft = none
    std::atomic<uint32_t> remaining{kFacePairCount};
};

// Packed result of one Line Space.
struct SpaceResult {
    std::vector<uint32_t> binaryWords;
    std::vector<uint32_t> candidateWords;
    std::vector<uint32_t> candidateData;
};

} // namespace

LineSpaces buildLineSpaces(const Bvh& bvh, const LineSpaceParams& params, Progress& progress) {
    if (params.n < 1 || params.n > CHCRT_LS_MAX_N) {
        throw InputError("Line Space resolution N must be in 1.." + std::to_string(CHCRT_LS_MAX_N) + ", got " +
                         std::to_string(params.n));
    }
    if (bvh.nodes.empty()) {
        throw InputError("Line Space build needs a non-empty BVH");
    }
    const auto start = std::chrono::steady_clock::now();
    LineSpaces result;
    result.params = params;
    result.bvhNodes = selectLineSpaceNodes(bvh, params.depth, params.triangleThreshold);
    result.spaceOfBvhNode.assign(bvh.nodes.size(), kNoSpace);
    for (size_t space = 0; space < result.bvhNodes.size(); ++space) {
        result.spaceOfBvhNode[result.bvhNodes[space]] = static_cast<uint32_t>(space);
    }
    const uint32_t n = params.n;
    const uint32_t spaceCount = static_cast<uint32_t>(result.bvhNodes.size());
    const uint32_t symmetricShafts = lsShaftCount(n, true), shafts = lsShaftCount(n, false);
    const double dilation = shaftDilationForScene(bvh.rootBounds());

    std::vector<std::unique_ptr<SpaceScratch>> scratch(spaceCount);
    std::vector<SpaceResult> packed(spaceCount);
    std::mutex scratchMutex;
    const uint64_t itemCount = uint64_t(spaceCount) * kFacePairCount;
    std::atomic<uint64_t> nextItem{0}, doneItems{0};
    progress.begin("Line Space " + params.toString(), itemCount);

    auto scratchFor = [&](uint32_t space) -> SpaceScratch& {
        std::lock_guard<std::mutex> lock(scratchMutex);
        if (!scratch[space]) {
            auto s = std::make_unique<SpaceScratch>();
            s->binary.assign(symmetricShafts, 0);
            if (params.candidates) {
                s->candidates.assign(shafts, kEmptyShaft);
            }
            scratch[space] = std::move(s);
        }
        return *scratch[space];
    };
    auto worker = [&] {
        for (uint64_t item = nextItem++; item < itemCount; item = nextItem++) {
            const uint32_t space = static_cast<uint32_t>(item / kFacePairCount);
            const uint32_t pair = static_cast<uint32_t>(item % kFacePairCount);
            const uint32_t node = result.bvhNodes[space];
            const Aabb box{bvh.nodes[node].boundsMin, bvh.nodes[node].boundsMax};
            SpaceScratch& s = scratchFor(space);
            fillBinaryFacePair(bvh, node, box, n, dilation, pair, s.binary);
            if (params.candidates) {
                fillCandidateFacePair(bvh, node, box, n, pair, s.binary, s.candidates);
            }
            // The last face pair of a node packs it (acq_rel: sees the other threads' writes to the scratch).
            if (s.remaining.fetch_sub(1, std::memory_order_acq_rel) == 1) {
                packed[space].binaryWords = packBits(s.binary);
                if (params.candidates) {
                    packSparse(s.candidates, packed[space].candidateWords, packed[space].candidateData);
                }
                std::lock_guard<std::mutex> lock(scratchMutex);
                scratch[space].reset();
            }
            progress.update(++doneItems);
        }
    };
    const uint32_t threadCount = std::max(1u, params.threads != 0 ? params.threads : std::thread::hardware_concurrency());
    std::vector<std::thread> threads;
    for (uint32_t t = 1; t < threadCount; ++t) {
        threads.emplace_back(worker);
    }
    worker();
    for (std::thread& t : threads) {
        t.join();
    }
    progress.end();

    // Assemble the pools in node order.
    const uint32_t words = lsWordCount(n, true);
    result.binaryWords.reserve(size_t(spaceCount) * words);
    result.candidates = SparseShaftStore(shafts);
    LineSpaceStats& stats = result.stats;
    for (uint32_t space = 0; space < spaceCount; ++space) {
        for (const uint32_t w : packed[space].binaryWords) {
            stats.binaryFilled += static_cast<uint64_t>(std::popcount(w));
        }
        result.binaryWords.insert(result.binaryWords.end(), packed[space].binaryWords.begin(),
                                  packed[space].binaryWords.end());
        if (params.candidates) {
            result.candidates.appendPacked(packed[space].candidateWords, packed[space].candidateData);
        }
        packed[space] = {};
    }
    stats.spaceCount = spaceCount;
    stats.binaryShafts = uint64_t(spaceCount) * symmetricShafts;
    stats.binaryBytes = 4ull * result.binaryWords.size();
    stats.candidateShafts = params.candidates ? uint64_t(spaceCount) * shafts : 0;
    stats.candidateFilled = result.candidates.filledCount();
    stats.candidateBytes = result.candidates.bytes();
    stats.nodeBytes = uint64_t(spaceCount) * sizeof(gpu::LineSpaceNodeGpu);
    stats.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

} // namespace chcrt::ls
