// The prepared-scene (.chs) reader: open (header, sizes, metadata, structure), read every subtree and its root
// node, summarise, and load the whole scene in core and as a proxy. Checksums would stop nearly every mutation at
// the first check, so the harness first recomputes each checksum whose range lies inside the input (header,
// metadata, subtree blobs): the structural validation behind them is what is fuzzed. The checksum checks
// themselves are covered by the seeds as they are and by tests/outofcore/chs_file_test.cpp. Files with LOD proxies
// (versions 2 and 3) also get their proxy blobs' checksums and the LOD directory's share of the metadata checksum
// recomputed; compact files (version 3) their blobs' checksums over the compact parts.
#include "renderer/outofcore/chs_file.h"
#include "tests/fuzz/fuzz_input.h"

#include <cstddef>
#include <cstring>
#include <vector>

namespace {

using namespace chcrt;
using namespace chcrt::outofcore;

bool inside(uint64_t offset, uint64_t bytes, uint64_t size) { return offset <= size && bytes <= size - offset; }

// A subtree or proxy blob's checksum (ChsFile::readBlob's and readCompactBlob's ranges), or false when the blob is
// not inside the input (or, compact, its size implies no vertex count).
bool blobChecksum(const std::vector<uint8_t>& b, uint64_t offset, uint64_t bytes, uint64_t nodeCount,
                  uint64_t triangleCount, bool uv, bool compact, uint64_t& sum) {
    std::vector<uint64_t> parts;
    if (compact) {
        const uint32_t vertices = chsCompactVertexCount(bytes, nodeCount, triangleCount, uv);
        if (vertices == UINT32_MAX) return false;
        parts = {(nodeCount + CHCRT_COMPACT_ROOT_TEXELS - 1) * 16, triangleCount * 16, uint64_t(vertices) * 12,
                 triangleCount * 4};
    } else {
        parts = {nodeCount * sizeof(BvhNodeGpu), triangleCount * sizeof(TriangleGpu)};
    }
    parts.push_back(triangleCount * 3 * sizeof(glm::vec3));
    parts.push_back(uv ? triangleCount * 3 * sizeof(glm::vec2) : 0);
    uint64_t total = 0;
    for (uint64_t p : parts) total += p;
    if (total > (uint64_t(1) << 40) || !inside(offset, total, b.size())) return false;
    const uint8_t* at = b.data() + offset;
    sum = 0;
    for (uint64_t p : parts) {
        sum = chsChecksum(at, p, sum);
        at += p;
    }
    return true;
}

void fixChecksums(std::vector<uint8_t>& b) {
    if (b.size() < sizeof(ChsHeader)) return;
    ChsHeader h;
    std::memcpy(&h, b.data(), sizeof(h));
    const uint64_t upperBytes = uint64_t(h.upperNodeCount) * sizeof(ChsUpperNode);
    const uint64_t recordBytes = uint64_t(h.subtreeCount) * sizeof(ChsSubtreeRecord);
    const uint64_t materialBytes = uint64_t(h.materialCount) * sizeof(ChsMaterialRecord);
    const uint64_t metaBytes = upperBytes + recordBytes + materialBytes + h.sourceBytes;
    if (inside(h.metaOffset, metaBytes, b.size())) {
        const uint8_t* meta = b.data() + h.metaOffset;
        const bool uv = (h.flags & kChsFlagTexcoords) != 0;
        const bool compact = (h.flags & kChsFlagCompact) != 0;
        for (uint32_t i = 0; i < h.subtreeCount; ++i) {
            ChsSubtreeRecord r;
            uint8_t* at = b.data() + h.metaOffset + upperBytes + uint64_t(i) * sizeof(ChsSubtreeRecord);
            std::memcpy(&r, at, sizeof(r));
            if (blobChecksum(b, r.offset, r.bytes, r.nodeCount, r.triangleCount, uv, compact, r.checksum)) {
                std::memcpy(at, &r, sizeof(r));
            }
        }
        uint64_t sum = chsChecksum(meta, upperBytes);
        sum = chsChecksum(meta + upperBytes, recordBytes, sum);
        sum = chsChecksum(meta + upperBytes + recordBytes, materialBytes, sum);
        sum = chsChecksum(meta + upperBytes + recordBytes + materialBytes, h.sourceBytes, sum);
        // The LOD directory (version 2) follows the source spec: its header, then levels records per subtree.
        const uint64_t lodAt = h.metaOffset + metaBytes;
        if ((h.flags & kChsFlagLod) != 0 && inside(lodAt, sizeof(ChsLodHeader), b.size())) {
            ChsLodHeader lod;
            std::memcpy(&lod, b.data() + lodAt, sizeof(lod));
            const uint64_t lodRecordBytes = uint64_t(h.subtreeCount) * lod.levels * sizeof(ChsLodRecord);
            if (lod.levels <= 8 && inside(lodAt + sizeof(lod), lodRecordBytes, b.size())) {
                uint8_t* records = b.data() + lodAt + sizeof(lod);
                for (uint64_t k = 0; k < lodRecordBytes / sizeof(ChsLodRecord); ++k) {
                    ChsLodRecord r;
                    std::memcpy(&r, records + k * sizeof(r), sizeof(r));
                    if (blobChecksum(b, r.offset, r.bytes, r.nodeCount, r.triangleCount, uv, compact, r.checksum)) {
                        std::memcpy(records + k * sizeof(r), &r, sizeof(r));
                    }
                }
                sum = chsChecksum(&lod, sizeof(lod), sum);
                sum = chsChecksum(records, lodRecordBytes, sum);
            }
        }
        h.metaChecksum = sum;
    }
    h.headerChecksum = chsChecksum(&h, offsetof(ChsHeader, headerChecksum));
    std::memcpy(b.data(), &h, sizeof(h));
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    std::vector<uint8_t> bytes(data, data + size);
    fixChecksums(bytes);
    const auto file = chcrt::fuzz::writeScratchFile(bytes.data(), bytes.size(), ".chs");
    chcrt::fuzz::expectOnlyInputErrors([&] {
        const ChsFile chs(file);
        (void)summarize(chs);
        (void)chs.light();
        for (uint32_t i = 0; i < chs.subtrees().size(); ++i) {
            (void)chs.readSubtreeNode(i, 0);
            (void)chs.readSubtree(i);
            for (uint32_t level = 1; level <= chs.lodLevels(); ++level) {
                if (chs.lodRecord(i, level).nodeCount != 0) (void)chs.readSubtree(i, level);
            }
        }
    });
    chcrt::fuzz::expectOnlyInputErrors([&] { (void)loadPreparedSceneProxy(file); });
    chcrt::fuzz::expectOnlyInputErrors([&] { (void)loadPreparedScene(file); });
    return 0;
}
