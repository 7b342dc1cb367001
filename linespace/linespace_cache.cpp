#include "linespace/linespace_cache.h"

#include "linespace/cache_file.h"
#include "linespace/shaft_index.h"

#include <bit>
#include <cstdio>

namespace chcrt::ls {

namespace {

// Same bytes as the format's first version (magic, version, N, D, T, candidates, 0): older files stay valid.
constexpr uint32_t kVersion = 1;

CacheFileHeader makeHeader(const LineSpaceParams& params, uint64_t inputHash) {
    return makeCacheFileHeader("CHCRTLS1", kVersion,
                               {params.n, params.depth, params.triangleThreshold, params.candidates ? 1u : 0u, 0u},
                               inputHash);
}

} // namespace

uint64_t lineSpaceInputHash(const Bvh& bvh) {
    uint64_t hash = fnv1a64(bvh.nodes.data(), bvh.nodes.size() * sizeof(BvhNodeGpu));
    return fnv1a64(bvh.triangles.data(), bvh.triangles.size() * sizeof(TriangleGpu), hash);
}

std::filesystem::path lineSpaceCachePath(const std::filesystem::path& dir, uint64_t inputHash,
                                         const LineSpaceParams& params) {
    char name[128];
    std::snprintf(name, sizeof(name), "linespace_%016llx_N%u_D%u_T%u_%s.bin",
                  static_cast<unsigned long long>(inputHash), params.n, params.depth, params.triangleThreshold,
                  params.candidates ? "candidates" : "binary");
    return dir / name;
}

void saveLineSpaceCache(const std::filesystem::path& file, uint64_t inputHash, const LineSpaces& spaces) {
    CacheWriter payload;
    payload.array(spaces.bvhNodes);
    payload.array(spaces.binaryWords);
    payload.array(spaces.candidates.words());
    payload.array(spaces.candidates.offsets());
    payload.array(spaces.candidates.data());
    payload.value(spaces.stats.buildSeconds);
    writeCacheFile(file, makeHeader(spaces.params, inputHash), payload.bytes, "Line Space cache");
}

CacheLoad loadLineSpaceCache(const std::filesystem::path& file, const Bvh& bvh, uint64_t inputHash,
                             const LineSpaceParams& params, LineSpaces& out) {
    std::vector<uint8_t> bytes;
    if (const CacheLoad read = readCacheFile(file, makeHeader(params, inputHash), bytes); read != CacheLoad::Loaded) {
        return read;
    }
    CacheReader reader(bytes);
    LineSpaces spaces;
    spaces.params = params;
    std::vector<uint32_t> words, offsets, data;
    double buildSeconds = 0.0;
    if (!reader.array(spaces.bvhNodes) || !reader.array(spaces.binaryWords) || !reader.array(words) ||
        !reader.array(offsets) || !reader.array(data) || !reader.value(buildSeconds) || !reader.atEnd()) {
        return CacheLoad::Corrupt;
    }
    // Structural checks beyond the checksum: the same cut of this BVH, sizes, candidate indices in range.
    if (spaces.bvhNodes != selectLineSpaceNodes(bvh, params.depth, params.triangleThreshold) ||
        spaces.binaryWords.size() != spaces.bvhNodes.size() * size_t(lsWordCount(params.n, true))) {
        return CacheLoad::Corrupt;
    }
    const uint32_t shafts = lsShaftCount(params.n, false);
    if (params.candidates) {
        if (!SparseShaftStore::fromPools(shafts, std::move(words), std::move(offsets), std::move(data),
                                         spaces.candidates) ||
            spaces.candidates.spaceCount() != spaces.bvhNodes.size()) {
            return CacheLoad::Corrupt;
        }
        for (const uint32_t triangle : spaces.candidates.data()) {
            if (triangle >= bvh.triangles.size()) {
                return CacheLoad::Corrupt;
            }
        }
    } else if (!words.empty() || !offsets.empty() || !data.empty()) {
        return CacheLoad::Corrupt;
    } else {
        spaces.candidates = SparseShaftStore(shafts);
    }
    spaces.spaceOfBvhNode.assign(bvh.nodes.size(), kNoSpace);
    for (size_t space = 0; space < spaces.bvhNodes.size(); ++space) {
        spaces.spaceOfBvhNode[spaces.bvhNodes[space]] = static_cast<uint32_t>(space);
    }
    LineSpaceStats& stats = spaces.stats;
    stats.buildSeconds = buildSeconds;
    stats.spaceCount = static_cast<uint32_t>(spaces.bvhNodes.size());
    stats.binaryShafts = uint64_t(stats.spaceCount) * lsShaftCount(params.n, true);
    for (const uint32_t w : spaces.binaryWords) {
        stats.binaryFilled += static_cast<uint64_t>(std::popcount(w));
    }
    stats.binaryBytes = 4ull * spaces.binaryWords.size();
    stats.candidateShafts = params.candidates ? uint64_t(stats.spaceCount) * shafts : 0;
    stats.candidateFilled = spaces.candidates.filledCount();
    stats.candidateBytes = spaces.candidates.bytes();
    stats.nodeBytes = uint64_t(stats.spaceCount) * sizeof(gpu::LineSpaceNodeGpu);
    out = std::move(spaces);
    return CacheLoad::Loaded;
}

LineSpaces loadOrBuildLineSpaces(const Bvh& bvh, const LineSpaceParams& params, const std::filesystem::path& cacheDir,
                                 Progress& progress, CacheOutcome* outcome) {
    if (cacheDir.empty()) {
        if (outcome != nullptr) *outcome = CacheOutcome::Built;
        return buildLineSpaces(bvh, params, progress);
    }
    const uint64_t hash = lineSpaceInputHash(bvh);
    const std::filesystem::path file = lineSpaceCachePath(cacheDir, hash, params);
    return loadOrBuildCached<LineSpaces>(
        [&](LineSpaces& spaces) { return loadLineSpaceCache(file, bvh, hash, params, spaces); },
        [&] { return buildLineSpaces(bvh, params, progress); },
        [&](const LineSpaces& spaces) { saveLineSpaceCache(file, hash, spaces); }, outcome);
}

} // namespace chcrt::ls
