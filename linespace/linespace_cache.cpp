#include "linespace/linespace_cache.h"

#include "linespace/shaft_index.h"
#include "renderer/core/error.h"

#include <bit>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <unistd.h>

namespace chcrt::ls {

namespace {

constexpr char kMagic[8] = {'C', 'H', 'C', 'R', 'T', 'L', 'S', '1'};
constexpr uint32_t kVersion = 1;

uint64_t fnv1a(const void* bytes, size_t size, uint64_t hash = 0xcbf29ce484222325ull) {
    const auto* p = static_cast<const uint8_t*>(bytes);
    for (size_t i = 0; i < size; ++i) {
        hash = (hash ^ p[i]) * 0x100000001b3ull;
    }
    return hash;
}

// Fixed-size header; every field is checked on load.
struct Header {
    char magic[8];
    uint32_t version;
    uint32_t n;
    uint32_t depth;
    uint32_t triangleThreshold;
    uint32_t candidates;
    uint32_t pad;
    uint64_t inputHash;
    uint64_t payloadBytes;
    uint64_t payloadChecksum;
};
static_assert(sizeof(Header) == 56);

class Writer {
public:
    template <typename T>
    void value(const T& v) {
        const auto* p = reinterpret_cast<const uint8_t*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    void array(const std::vector<uint32_t>& v) {
        value<uint64_t>(v.size());
        const auto* p = reinterpret_cast<const uint8_t*>(v.data());
        bytes.insert(bytes.end(), p, p + v.size() * sizeof(uint32_t));
    }
    std::vector<uint8_t> bytes;
};

class Reader {
public:
    explicit Reader(const std::vector<uint8_t>& b) : bytes(b) {}
    template <typename T>
    bool value(T& v) {
        if (bytes.size() - position < sizeof(T)) {
            return false;
        }
        std::memcpy(&v, bytes.data() + position, sizeof(T));
        position += sizeof(T);
        return true;
    }
    bool array(std::vector<uint32_t>& v) {
        uint64_t count = 0;
        if (!value(count) || count > (bytes.size() - position) / sizeof(uint32_t)) {
            return false;
        }
        v.resize(count);
        if (count != 0) { // memcpy to an empty vector's null data() is undefined even for 0 bytes
            std::memcpy(v.data(), bytes.data() + position, count * sizeof(uint32_t));
        }
        position += count * sizeof(uint32_t);
        return true;
    }
    bool atEnd() const { return position == bytes.size(); }

private:
    const std::vector<uint8_t>& bytes;
    size_t position = 0;
};

Header makeHeader(const LineSpaceParams& params, uint64_t inputHash) {
    Header h{};
    std::memcpy(h.magic, kMagic, sizeof(kMagic));
    h.version = kVersion;
    h.n = params.n;
    h.depth = params.depth;
    h.triangleThreshold = params.triangleThreshold;
    h.candidates = params.candidates ? 1u : 0u;
    h.inputHash = inputHash;
    return h;
}

} // namespace

uint64_t lineSpaceInputHash(const Bvh& bvh) {
    uint64_t hash = fnv1a(bvh.nodes.data(), bvh.nodes.size() * sizeof(BvhNodeGpu));
    return fnv1a(bvh.triangles.data(), bvh.triangles.size() * sizeof(TriangleGpu), hash);
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
    Writer payload;
    payload.array(spaces.bvhNodes);
    payload.array(spaces.binaryWords);
    payload.array(spaces.candidates.words());
    payload.array(spaces.candidates.offsets());
    payload.array(spaces.candidates.data());
    payload.value(spaces.stats.buildSeconds);
    Header header = makeHeader(spaces.params, inputHash);
    header.payloadBytes = payload.bytes.size();
    header.payloadChecksum = fnv1a(payload.bytes.data(), payload.bytes.size());

    std::error_code ec;
    if (!file.parent_path().empty()) {
        std::filesystem::create_directories(file.parent_path(), ec);
    }
    // Unique temporary name in the same directory, then rename: readers see the old file or the whole new one.
    std::filesystem::path temporary = file;
    temporary += ".tmp." + std::to_string(::getpid());
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(&header), sizeof(header));
        out.write(reinterpret_cast<const char*>(payload.bytes.data()), std::streamsize(payload.bytes.size()));
        out.flush();
        if (!out) {
            std::filesystem::remove(temporary, ec);
            throw InputError("cannot write Line Space cache " + temporary.string());
        }
    }
    std::filesystem::rename(temporary, file, ec);
    if (ec) {
        std::filesystem::remove(temporary, ec);
        throw InputError("cannot move Line Space cache into place: " + file.string());
    }
}

CacheLoad loadLineSpaceCache(const std::filesystem::path& file, const Bvh& bvh, uint64_t inputHash,
                             const LineSpaceParams& params, LineSpaces& out) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        return CacheLoad::Missing;
    }
    Header header{};
    if (!in.read(reinterpret_cast<char*>(&header), sizeof(header))) {
        return CacheLoad::Corrupt;
    }
    const Header expected = makeHeader(params, inputHash);
    // Everything before the payload size must match byte for byte (magic, version, parameters, padding, hash).
    if (std::memcmp(&header, &expected, offsetof(Header, payloadBytes)) != 0 || header.payloadBytes > (uint64_t(1) << 40)) {
        return CacheLoad::Corrupt;
    }
    std::vector<uint8_t> bytes(header.payloadBytes);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size())) || in.peek() != EOF ||
        fnv1a(bytes.data(), bytes.size()) != header.payloadChecksum) {
        return CacheLoad::Corrupt;
    }
    Reader reader(bytes);
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

const char* toString(CacheOutcome outcome) {
    switch (outcome) {
    case CacheOutcome::Loaded:
        return "loaded from cache";
    case CacheOutcome::Built:
        return "built";
    case CacheOutcome::RebuiltCorrupt:
        return "rebuilt (cache file was corrupt or stale)";
    }
    return "?";
}

LineSpaces loadOrBuildLineSpaces(const Bvh& bvh, const LineSpaceParams& params, const std::filesystem::path& cacheDir,
                                 Progress& progress, CacheOutcome* outcome) {
    CacheOutcome result = CacheOutcome::Built;
    if (!cacheDir.empty()) {
        const uint64_t hash = lineSpaceInputHash(bvh);
        const std::filesystem::path file = lineSpaceCachePath(cacheDir, hash, params);
        LineSpaces loaded;
        const CacheLoad load = loadLineSpaceCache(file, bvh, hash, params, loaded);
        if (load == CacheLoad::Loaded) {
            if (outcome != nullptr) {
                *outcome = CacheOutcome::Loaded;
            }
            return loaded;
        }
        result = load == CacheLoad::Corrupt ? CacheOutcome::RebuiltCorrupt : CacheOutcome::Built;
        LineSpaces built = buildLineSpaces(bvh, params, progress);
        saveLineSpaceCache(file, hash, built);
        if (outcome != nullptr) {
            *outcome = result;
        }
        return built;
    }
    if (outcome != nullptr) {
        *outcome = result;
    }
    return buildLineSpaces(bvh, params, progress);
}

} // namespace chcrt::ls
