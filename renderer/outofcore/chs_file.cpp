#include "renderer/outofcore/chs_file.h"

#include "renderer/core/error.h"
#include "renderer/outofcore/compact_subtree.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>

namespace chcrt::outofcore {
namespace {

// Test hook (docs/robustness.md): CHCRT_FAULT_CHS_EIO=FIRST[-LAST] makes the subtree reads numbered FIRST to LAST
// (0-based, counted over the process's ChsFile::readSubtree calls; FIRST- = every read from FIRST on; one number =
// that read only) fail with EIO in pread, as a failing disk would. Malformed values are ignored.
bool injectedReadError() {
    struct Range {
        bool on = false;
        uint64_t first = 0, last = 0;
    };
    static const Range range = [] {
        Range r;
        const char* text = std::getenv("CHCRT_FAULT_CHS_EIO");
        if (text == nullptr || *text == '\0') return r;
        char* end = nullptr;
        r.first = std::strtoull(text, &end, 10);
        if (end == text) return r;
        r.last = r.first;
        if (*end == '-') {
            char* rest = end + 1;
            if (*rest == '\0') r.last = UINT64_MAX, end = rest;
            else r.last = std::strtoull(rest, &end, 10);
        }
        r.on = *end == '\0' && r.last >= r.first;
        return r;
    }();
    static std::atomic<uint64_t> reads{0};
    if (!range.on) return false;
    const uint64_t n = reads.fetch_add(1);
    return n >= range.first && n <= range.last;
}

void readExact(int fd, void* data, uint64_t bytes, uint64_t offset, const std::string& what, bool failWithEio = false) {
    auto* p = static_cast<char*>(data);
    while (bytes > 0) {
        ssize_t got = -1;
        if (failWithEio) errno = EIO;
        else got = ::pread(fd, p, bytes, off_t(offset));
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) throw InputError(what + (got < 0 ? std::string(": ") + std::strerror(errno) : ": file is truncated"));
        p += got, bytes -= uint64_t(got), offset += uint64_t(got);
    }
}

// Elements `indices` of an array of `stride`-byte elements at file offset `at`, read in ascending order: indices
// within kGatherGapBytes of the previous one share its read, up to kGatherRunBytes a read. The triangles one frame's
// pixels hit cluster in a subtree's arrays, and a read of a few KB from the page cache costs about what one of 16
// bytes does (the primary resolve read 4 elements a triangle one by one: 125 ms of a far frame of the 140M city).
// `order` lists the positions of `indices` in ascending order of index (ascendingOrder); `visit(k, bytes)` gets each
// index's position in `indices` and its element.
constexpr uint64_t kGatherGapBytes = 4096, kGatherRunBytes = 256 * 1024;

std::vector<uint32_t> ascendingOrder(std::span<const uint32_t> indices) {
    std::vector<uint32_t> order(indices.size());
    for (uint32_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return indices[a] < indices[b]; });
    return order;
}

template <class Visit>
void readGathered(int fd, uint64_t at, uint64_t stride, std::span<const uint32_t> indices,
                  const std::vector<uint32_t>& order, std::vector<char>& buffer, const std::string& what, Visit&& visit) {
    for (size_t i = 0; i < order.size();) {
        const uint64_t first = indices[order[i]];
        size_t j = i + 1;
        while (j < order.size() && (uint64_t(indices[order[j]]) - indices[order[j - 1]]) * stride <= kGatherGapBytes &&
               (uint64_t(indices[order[j]]) - first + 1) * stride <= kGatherRunBytes) {
            ++j;
        }
        const uint64_t bytes = (uint64_t(indices[order[j - 1]]) - first + 1) * stride;
        buffer.resize(bytes);
        readExact(fd, buffer.data(), bytes, at + first * stride, what);
        for (size_t k = i; k < j; ++k) visit(order[k], buffer.data() + (indices[order[k]] - first) * stride);
        i = j;
    }
}

} // namespace

ChsFile::ChsFile(const std::filesystem::path& file) : path_(file) {
    const std::string name = file.string();
    fd_ = ::open(name.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw InputError("cannot open prepared scene " + name + ": " + std::strerror(errno));
    try {
        validate();
    } catch (...) {
        ::close(fd_); // the destructor does not run for a throwing constructor
        fd_ = -1;
        throw;
    }
}

void ChsFile::validate() {
    const std::string name = path_.string();
    struct stat st {};
    if (::fstat(fd_, &st) != 0) throw InputError("cannot stat " + name + ": " + std::strerror(errno));
    const uint64_t size = uint64_t(st.st_size);
    if (size < sizeof(ChsHeader)) throw InputError(name + ": not a prepared scene (file is truncated or too small)");
    readExact(fd_, &header_, sizeof(header_), 0, name);
    const ChsHeader& h = header_;
    if (std::memcmp(h.magic, kChsMagic, sizeof(h.magic)) != 0) throw InputError(name + ": not a prepared scene (bad magic)");
    const bool lod = (h.flags & kChsFlagLod) != 0;
    const bool compact = (h.flags & kChsFlagCompact) != 0;
    if (h.version != kChsVersion && h.version != kChsVersionLod && h.version != kChsVersionCompact) {
        throw InputError(name + ": prepared scene version " + std::to_string(h.version) + ", this build reads versions " +
                         std::to_string(kChsVersion) + " to " + std::to_string(kChsVersionCompact) + " (prepare it again)");
    }
    if (h.headerBytes != sizeof(ChsHeader) || h.headerChecksum != chsChecksum(&h, offsetof(ChsHeader, headerChecksum))) {
        throw InputError(name + ": corrupted prepared scene (header checksum mismatch)");
    }
    if (h.version != kChsVersionCompact && lod != (h.version == kChsVersionLod)) {
        throw InputError(name + ": corrupted prepared scene (version " + std::to_string(h.version) +
                         (lod ? " with" : " without") + " LOD proxies)");
    }
    if (compact != (h.version == kChsVersionCompact)) {
        throw InputError(name + ": corrupted prepared scene (version " + std::to_string(h.version) +
                         (compact ? " with" : " without") + " compact subtrees)");
    }
    if (h.fileBytes != size) {
        throw InputError(name + ": truncated or extended prepared scene (" + std::to_string(size) + " bytes, header says " +
                         std::to_string(h.fileBytes) + ")");
    }
    const uint64_t baseMeta = uint64_t(h.upperNodeCount) * sizeof(ChsUpperNode) +
                              uint64_t(h.subtreeCount) * sizeof(ChsSubtreeRecord) +
                              uint64_t(h.materialCount) * sizeof(ChsMaterialRecord) + h.sourceBytes;
    uint64_t metaExpected = baseMeta;
    if (lod) { // the LOD directory ends the metadata; its header says how many levels follow
        if (h.metaOffset > size || baseMeta + sizeof(ChsLodHeader) > size - h.metaOffset) {
            throw InputError(name + ": corrupted prepared scene (inconsistent sizes in the header)");
        }
        readExact(fd_, &lod_, sizeof(lod_), h.metaOffset + baseMeta, name);
        if (lod_.levels == 0 || lod_.levels > 8 || lod_.coarsestRatio < 2) {
            throw InputError(name + ": corrupted prepared scene (LOD directory header)");
        }
        metaExpected += sizeof(ChsLodHeader) + uint64_t(h.subtreeCount) * lod_.levels * sizeof(ChsLodRecord);
    }
    if (h.metaBytes != metaExpected || h.metaOffset < sizeof(ChsHeader) || h.metaOffset > size || h.metaOffset + h.metaBytes != size ||
        h.subtreeCount == 0 || h.upperNodeCount == 0) {
        throw InputError(name + ": corrupted prepared scene (inconsistent sizes in the header)");
    }
    // Counts the header claims beyond what the subtree area could hold (every triangle takes at least its record
    // and normals, every node its record) are refused before anything is sized by them.
    const uint64_t subtreeArea = h.metaOffset - sizeof(ChsHeader);
    const uint64_t triangleMin =
        compact ? chsCompactFixedBytes(0, 1, false) - chsCompactFixedBytes(0, 0, false) : sizeof(TriangleGpu) + 36;
    const uint64_t nodeMin = compact ? 16 : sizeof(BvhNodeGpu);
    if (h.triangleCount > subtreeArea / triangleMin || h.nodeCount > subtreeArea / nodeMin ||
        h.maxSubtreeTriangles > subtreeArea / triangleMin || h.maxSubtreeNodes > subtreeArea / nodeMin) {
        throw InputError(name + ": corrupted prepared scene (the header claims " + std::to_string(h.triangleCount) +
                         " triangles and " + std::to_string(h.nodeCount) + " nodes, more than its " +
                         std::to_string(subtreeArea) + " bytes of subtrees can hold)");
    }
    upper_.resize(h.upperNodeCount);
    subtrees_.resize(h.subtreeCount);
    materials_.resize(h.materialCount);
    source_.resize(h.sourceBytes);
    uint64_t at = h.metaOffset;
    readExact(fd_, upper_.data(), upper_.size() * sizeof(ChsUpperNode), at, name);
    at += upper_.size() * sizeof(ChsUpperNode);
    readExact(fd_, subtrees_.data(), subtrees_.size() * sizeof(ChsSubtreeRecord), at, name);
    at += subtrees_.size() * sizeof(ChsSubtreeRecord);
    readExact(fd_, materials_.data(), materials_.size() * sizeof(ChsMaterialRecord), at, name);
    at += materials_.size() * sizeof(ChsMaterialRecord);
    readExact(fd_, source_.data(), source_.size(), at, name);
    at += source_.size();
    uint64_t sum = chsChecksum(upper_.data(), upper_.size() * sizeof(ChsUpperNode));
    sum = chsChecksum(subtrees_.data(), subtrees_.size() * sizeof(ChsSubtreeRecord), sum);
    sum = chsChecksum(materials_.data(), materials_.size() * sizeof(ChsMaterialRecord), sum);
    sum = chsChecksum(source_.data(), source_.size(), sum);
    if (lod) {
        lodRecords_.resize(size_t(h.subtreeCount) * lod_.levels);
        readExact(fd_, lodRecords_.data(), lodRecords_.size() * sizeof(ChsLodRecord), at + sizeof(ChsLodHeader), name);
        sum = chsChecksum(&lod_, sizeof(lod_), sum);
        sum = chsChecksum(lodRecords_.data(), lodRecords_.size() * sizeof(ChsLodRecord), sum);
    }
    if (sum != h.metaChecksum) throw InputError(name + ": corrupted prepared scene (metadata checksum mismatch)");
    // Structure: children in range and after their parent, every subtree referenced from its upper node, blobs
    // inside the subtree area and of the size their counts imply.
    const bool uv = hasTexcoords();
    for (uint32_t i = 0; i < h.upperNodeCount; ++i) {
        const ChsUpperNode& u = upper_[i];
        const bool ok = u.subtree == kChsNoSubtree
                            ? (u.firstChild > i && uint64_t(u.firstChild) + 1 < h.upperNodeCount)
                            : (u.subtree < h.subtreeCount && subtrees_[u.subtree].upperNode == i);
        if (!ok) throw InputError(name + ": corrupted prepared scene (upper node " + std::to_string(i) + ")");
    }
    // The blob's size as its counts imply; a compact blob's vertex count is what its size leaves (at most 3 per
    // triangle): recorded for the reads and the GPU cache's slots.
    auto sizeMatches = [&](uint64_t bytes, uint32_t nodes, uint32_t triangles, std::vector<uint32_t>& vertices) {
        if (!compact) return bytes == chsSubtreeBytes(nodes, triangles, uv);
        vertices.push_back(chsCompactVertexCount(bytes, nodes, triangles, uv));
        return vertices.back() != UINT32_MAX;
    };
    for (uint32_t i = 0; i < h.subtreeCount; ++i) {
        const ChsSubtreeRecord& r = subtrees_[i];
        if (r.nodeCount == 0 || r.nodeCount > h.maxSubtreeNodes || r.triangleCount > h.maxSubtreeTriangles ||
            !sizeMatches(r.bytes, r.nodeCount, r.triangleCount, subtreeVertices_) || r.offset < sizeof(ChsHeader) ||
            r.offset > h.metaOffset || r.bytes > h.metaOffset - r.offset || r.upperNode >= h.upperNodeCount) {
            throw InputError(name + ": corrupted prepared scene (subtree record " + std::to_string(i) + ")");
        }
    }
    for (uint32_t v : subtreeVertices_) maxSubtreeVertices_ = std::max(maxSubtreeVertices_, v);
    if (lod && (lod_.maxProxyNodes > subtreeArea / nodeMin || lod_.maxProxyTriangles > subtreeArea / triangleMin)) {
        throw InputError(name + ": corrupted prepared scene (LOD directory header)");
    }
    for (size_t i = 0; i < lodRecords_.size(); ++i) {
        const ChsLodRecord& r = lodRecords_[i];
        const bool kept = r.nodeCount != 0;
        if (compact && !kept) lodVertices_.push_back(0);
        const bool ok = std::isfinite(r.errorWorld) && r.errorWorld >= 0.0f &&
                        (!kept ? r.triangleCount == 0 && r.bytes == 0
                               : r.nodeCount <= lod_.maxProxyNodes && r.triangleCount <= lod_.maxProxyTriangles &&
                                     sizeMatches(r.bytes, r.nodeCount, r.triangleCount, lodVertices_) &&
                                     r.offset >= sizeof(ChsHeader) && r.offset <= h.metaOffset &&
                                     r.bytes <= h.metaOffset - r.offset);
        if (!ok) {
            throw InputError(name + ": corrupted prepared scene (LOD record " + std::to_string(i / lod_.levels) + "." +
                             std::to_string(i % lod_.levels + 1) + ")");
        }
    }
    for (uint32_t v : lodVertices_) maxProxyVertices_ = std::max(maxProxyVertices_, v);
}

uint32_t ChsFile::vertexCount(uint32_t index, uint32_t level) const {
    if (!compact()) return 0;
    if (level == 0) {
        if (index >= subtreeVertices_.size()) throw InputError(path_.string() + ": no subtree " + std::to_string(index));
        return subtreeVertices_[index];
    }
    (void)lodRecord(index, level); // range checks
    return lodVertices_[size_t(index) * lod_.levels + level - 1];
}

ChsFile::~ChsFile() {
    if (fd_ >= 0) ::close(fd_);
}

AreaLight ChsFile::light() const {
    AreaLight l;
    const float* f = header_.light;
    l.corner = {f[0], f[1], f[2]};
    l.edgeU = {f[3], f[4], f[5]};
    l.edgeV = {f[6], f[7], f[8]};
    l.radiance = {f[9], f[10], f[11]};
    return l;
}

BvhNodeGpu ChsFile::readSubtreeNode(uint32_t index, uint32_t localNode) const {
    if (index >= subtrees_.size() || localNode >= subtrees_[index].nodeCount) {
        throw InputError(path_.string() + ": no node " + std::to_string(localNode) + " in subtree " + std::to_string(index));
    }
    const std::string what = path_.string() + ": reading subtree " + std::to_string(index);
    BvhNodeGpu node;
    if (!compact()) {
        readExact(fd_, &node, sizeof(node), subtrees_[index].offset + uint64_t(localNode) * sizeof(BvhNodeGpu), what);
        return node;
    }
    // The root (the frame) and the node's texel.
    glm::uvec4 root[CHCRT_COMPACT_ROOT_TEXELS], texel;
    readExact(fd_, root, sizeof(root), subtrees_[index].offset, what);
    texel = root[0];
    if (localNode != 0) {
        readExact(fd_, &texel, sizeof(texel),
                  subtrees_[index].offset + uint64_t(compactNodeTexel(localNode)) * sizeof(glm::uvec4), what);
    }
    return decodeCompactNode(root, texel, localNode == 0);
}

SubtreeData ChsFile::readSubtree(uint32_t index) const {
    SubtreeData d;
    readSubtree(index, 0, d);
    return d;
}

const ChsLodRecord& ChsFile::lodRecord(uint32_t subtree, uint32_t level) const {
    if (subtree >= subtrees_.size() || level == 0 || level > lodLevels()) {
        throw InputError(path_.string() + ": no LOD level " + std::to_string(level) + " of subtree " + std::to_string(subtree));
    }
    return lodRecords_[size_t(subtree) * lod_.levels + level - 1];
}

SubtreeData ChsFile::readSubtree(uint32_t index, uint32_t level) const {
    SubtreeData d;
    readSubtree(index, level, d);
    return d;
}

void ChsFile::readSubtree(uint32_t index, uint32_t level, SubtreeData& into, bool attributes, bool decode) const {
    if (level == 0) {
        if (index >= subtrees_.size()) throw InputError(path_.string() + ": no subtree " + std::to_string(index));
        const ChsSubtreeRecord& r = subtrees_[index];
        readBlob(r.offset, r.nodeCount, r.triangleCount, vertexCount(index), r.checksum, "subtree " + std::to_string(index),
                 into, attributes, decode);
        return;
    }
    const ChsLodRecord& r = lodRecord(index, level);
    const std::string what = "subtree " + std::to_string(index) + " LOD " + std::to_string(level);
    if (r.nodeCount == 0) throw InputError(path_.string() + ": no proxy stored for " + what);
    readBlob(r.offset, r.nodeCount, r.triangleCount, vertexCount(index, level), r.checksum, what, into, attributes, decode);
}

void ChsFile::readBlob(uint64_t offset, uint32_t nodeCount, uint32_t triangleCount, uint32_t vertexCount,
                       uint64_t checksum, const std::string& blob, SubtreeData& d, bool attributes, bool decode) const {
    if (compact()) {
        readCompactBlob(offset, nodeCount, triangleCount, vertexCount, checksum, blob, d, attributes, decode);
        return;
    }
    d.compactNodes.clear(), d.compactTriangles.clear(), d.vertices.clear(), d.materials.clear();
    const FileState before = fileState();
    // Without the attributes only a blob verified in this state: the checksum needs the whole blob.
    const bool partial = !attributes && blobVerified(offset, before);
    d.nodes.resize(nodeCount);
    d.triangles.resize(triangleCount);
    d.normals.resize(partial ? 0 : size_t(triangleCount) * 3);
    d.texcoords.resize(!partial && hasTexcoords() ? size_t(triangleCount) * 3 : 0);
    d.attributes = !partial;
    const std::string what = path_.string() + ": reading " + blob;
    uint64_t at = offset;
    bool fail = injectedReadError();
    auto read = [&](void* data, uint64_t bytes) {
        readExact(fd_, data, bytes, at, what, std::exchange(fail, false));
        at += bytes;
    };
    read(d.nodes.data(), d.nodes.size() * sizeof(BvhNodeGpu));
    read(d.triangles.data(), d.triangles.size() * sizeof(TriangleGpu));
    read(d.normals.data(), d.normals.size() * sizeof(glm::vec3));
    read(d.texcoords.data(), d.texcoords.size() * sizeof(glm::vec2));
    // The checksum once per blob and file state: summing every read was a quarter of an exact far frame of the
    // 140M city, whose blobs are read again and again through a host store smaller than the view needs
    // (docs/outofcore.md). A file truncated or overwritten under the open descriptor changes its size or times,
    // which empties the verified set; the state is taken before and after the read, so a change during it counts.
    const FileState after = fileState();
    if (partial && after != before) {
        // The file changed during a read that cannot be verified: read and verify the whole blob.
        readBlob(offset, nodeCount, triangleCount, vertexCount, checksum, blob, d, true, decode);
        return;
    }
    if (!partial && (after != before || !blobVerified(offset, after))) {
        uint64_t sum = chsChecksum(d.nodes.data(), d.nodes.size() * sizeof(BvhNodeGpu));
        sum = chsChecksum(d.triangles.data(), d.triangles.size() * sizeof(TriangleGpu), sum);
        sum = chsChecksum(d.normals.data(), d.normals.size() * sizeof(glm::vec3), sum);
        sum = chsChecksum(d.texcoords.data(), d.texcoords.size() * sizeof(glm::vec2), sum);
        if (sum != checksum) throw InputError(path_.string() + ": corrupted prepared scene (" + blob + " checksum mismatch)");
        if (after == before) markVerified(offset, after);
    }
    // Local indices in range (a checksum collision must not turn into out-of-bounds GPU reads).
    for (uint32_t k = 0; k < nodeCount; ++k) {
        const BvhNodeGpu& n = d.nodes[k];
        const bool ok = n.triCount == 0 ? (n.leftFirst > k && uint64_t(n.leftFirst) + 1 < nodeCount)
                                        : uint64_t(n.leftFirst) + n.triCount <= triangleCount;
        if (!ok) throw InputError(path_.string() + ": corrupted prepared scene (" + blob + " node " + std::to_string(k) + ")");
    }
}

// A compact blob (version 3): the GPU payload (node and triangle texels, vertices) with one pread each part, then
// for a whole read the materials and attributes; `decode`: also nodes and triangles in the full layout.
void ChsFile::readCompactBlob(uint64_t offset, uint32_t nodeCount, uint32_t triangleCount, uint32_t vertexCount,
                              uint64_t checksum, const std::string& blob, SubtreeData& d, bool attributes,
                              bool decode) const {
    const FileState before = fileState();
    const bool partial = !attributes && blobVerified(offset, before);
    d.compactNodes.resize(compactNodeTexels(nodeCount));
    d.compactTriangles.resize(triangleCount);
    d.vertices.resize(vertexCount);
    d.materials.resize(partial ? 0 : triangleCount);
    d.normals.resize(partial ? 0 : size_t(triangleCount) * 3);
    d.texcoords.resize(!partial && hasTexcoords() ? size_t(triangleCount) * 3 : 0);
    d.attributes = !partial;
    const std::string what = path_.string() + ": reading " + blob;
    uint64_t at = offset;
    bool fail = injectedReadError();
    auto read = [&](void* data, uint64_t bytes) {
        readExact(fd_, data, bytes, at, what, std::exchange(fail, false));
        at += bytes;
    };
    read(d.compactNodes.data(), d.compactNodes.size() * sizeof(glm::uvec4));
    read(d.compactTriangles.data(), d.compactTriangles.size() * sizeof(glm::uvec4));
    read(d.vertices.data(), d.vertices.size() * sizeof(glm::vec3));
    read(d.materials.data(), d.materials.size() * sizeof(uint32_t));
    read(d.normals.data(), d.normals.size() * sizeof(glm::vec3));
    read(d.texcoords.data(), d.texcoords.size() * sizeof(glm::vec2));
    const FileState after = fileState(); // as readBlob: verified once per blob and file state
    if (partial && after != before) {
        readCompactBlob(offset, nodeCount, triangleCount, vertexCount, checksum, blob, d, true, decode);
        return;
    }
    if (!partial && (after != before || !blobVerified(offset, after))) {
        uint64_t sum = chsChecksum(d.compactNodes.data(), d.compactNodes.size() * sizeof(glm::uvec4));
        sum = chsChecksum(d.compactTriangles.data(), d.compactTriangles.size() * sizeof(glm::uvec4), sum);
        sum = chsChecksum(d.vertices.data(), d.vertices.size() * sizeof(glm::vec3), sum);
        sum = chsChecksum(d.materials.data(), d.materials.size() * sizeof(uint32_t), sum);
        sum = chsChecksum(d.normals.data(), d.normals.size() * sizeof(glm::vec3), sum);
        sum = chsChecksum(d.texcoords.data(), d.texcoords.size() * sizeof(glm::vec2), sum);
        if (sum != checksum) throw InputError(path_.string() + ": corrupted prepared scene (" + blob + " checksum mismatch)");
        if (after == before) markVerified(offset, after);
    }
    // Local indices in range on every read (a checksum collision must not turn into out-of-bounds GPU reads).
    try {
        if (!decode) {
            checkCompactNodes(d.compactNodes, triangleCount);
            checkCompactTriangles(d.compactTriangles, vertexCount);
            d.nodes.clear(), d.triangles.clear();
            return;
        }
        d.nodes.resize(nodeCount);
        d.triangles.resize(triangleCount);
        decodeCompactNodes(d.compactNodes, triangleCount, d.nodes.data());
        decodeCompactTriangles(d.compactTriangles, d.vertices, d.materials, d.triangles.data());
    } catch (const InputError& e) {
        throw InputError(path_.string() + ": " + e.what() + " in " + blob);
    }
}

bool ChsFile::readTriangles(uint32_t index, std::span<const uint32_t> locals, TriangleGpu* triangles,
                            glm::vec3* normals) const {
    if (index >= subtrees_.size()) return false;
    const ChsSubtreeRecord& r = subtrees_[index];
    for (uint32_t local : locals) {
        if (local >= r.triangleCount) return false;
    }
    const FileState before = fileState();
    if (!blobVerified(r.offset, before)) return false;
    const std::string what = path_.string() + ": reading subtree " + std::to_string(index);
    const std::vector<uint32_t> order = ascendingOrder(locals); // shared by every part indexed by triangle
    std::vector<char> buffer;
    if (compact()) {
        // The blob's parts in order: triangle texels (three local vertex indices and the original id), vertices,
        // material ids, normals; each part's elements gathered (readGathered).
        const uint32_t vertexTotal = vertexCount(index);
        const uint64_t triangleAt = r.offset + compactNodeTexels(r.nodeCount) * sizeof(glm::uvec4);
        const uint64_t vertexAt = triangleAt + uint64_t(r.triangleCount) * sizeof(glm::uvec4);
        const uint64_t materialAt = vertexAt + uint64_t(vertexTotal) * sizeof(glm::vec3);
        const uint64_t normalAt = materialAt + uint64_t(r.triangleCount) * sizeof(uint32_t);
        std::vector<uint32_t> vertices(3 * locals.size());
        bool inRange = true;
        readGathered(fd_, triangleAt, sizeof(glm::uvec4), locals, order, buffer, what, [&](uint32_t k, const char* e) {
            glm::uvec4 t;
            std::memcpy(&t, e, sizeof t);
            inRange = inRange && t.x < vertexTotal && t.y < vertexTotal && t.z < vertexTotal;
            vertices[3 * k] = t.x, vertices[3 * k + 1] = t.y, vertices[3 * k + 2] = t.z;
            triangles[k].originalId = t.w;
            triangles[k].pad = 0;
        });
        if (!inRange) return false;
        readGathered(fd_, vertexAt, sizeof(glm::vec3), vertices, ascendingOrder(vertices), buffer, what,
                     [&](uint32_t k, const char* e) {
                         glm::vec3& v = k % 3 == 0   ? triangles[k / 3].v0
                                        : k % 3 == 1 ? triangles[k / 3].v1
                                                     : triangles[k / 3].v2;
                         std::memcpy(&v, e, sizeof v);
                     });
        readGathered(fd_, materialAt, sizeof(uint32_t), locals, order, buffer, what,
                     [&](uint32_t k, const char* e) { std::memcpy(&triangles[k].materialId, e, sizeof(uint32_t)); });
        readGathered(fd_, normalAt, 3 * sizeof(glm::vec3), locals, order, buffer, what,
                     [&](uint32_t k, const char* e) { std::memcpy(&normals[3 * k], e, 3 * sizeof(glm::vec3)); });
        return fileState() == before;
    }
    const uint64_t first = r.offset + uint64_t(r.nodeCount) * sizeof(BvhNodeGpu);
    const uint64_t firstNormal = first + uint64_t(r.triangleCount) * sizeof(TriangleGpu);
    readGathered(fd_, first, sizeof(TriangleGpu), locals, order, buffer, what,
                 [&](uint32_t k, const char* e) { std::memcpy(&triangles[k], e, sizeof(TriangleGpu)); });
    readGathered(fd_, firstNormal, 3 * sizeof(glm::vec3), locals, order, buffer, what,
                 [&](uint32_t k, const char* e) { std::memcpy(&normals[3 * k], e, 3 * sizeof(glm::vec3)); });
    return fileState() == before;
}

ChsFile::FileState ChsFile::fileState() const {
    struct stat st {};
    if (::fstat(fd_, &st) != 0) throw InputError("cannot stat " + path_.string() + ": " + std::strerror(errno));
    return {uint64_t(st.st_size), int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec,
            int64_t(st.st_ctim.tv_sec) * 1000000000 + st.st_ctim.tv_nsec};
}

bool ChsFile::blobVerified(uint64_t offset, const FileState& state) const {
    std::lock_guard<std::mutex> lock(verifiedMutex_);
    return state == verifiedState_ && verifiedBlobs_.count(offset) != 0;
}

void ChsFile::markVerified(uint64_t offset, const FileState& state) const {
    std::lock_guard<std::mutex> lock(verifiedMutex_);
    if (state != verifiedState_) {
        verifiedBlobs_.clear();
        verifiedState_ = state;
    }
    verifiedBlobs_.insert(offset);
}

bool isPreparedScenePath(const std::string& scene) {
    return std::filesystem::path(scene).extension() == ".chs";
}

namespace {

// Name, light, source, materials and stored camera of a prepared scene (no geometry).
void loadMetadata(const ChsFile& chs, const std::filesystem::path& file, LoadedPreparedScene& out) {
    const ChsHeader& h = chs.header();
    out.source = chs.source();
    out.light = chs.light();
    Scene& scene = out.scene;
    scene.name = file.stem().string();
    for (const ChsMaterialRecord& m : chs.materials()) {
        Material material;
        material.baseColorFactor = {m.baseColor[0], m.baseColor[1], m.baseColor[2], m.baseColor[3]};
        material.baseColorTexture = -1; // textures are not stored in .chs files
        material.name.assign(m.name, strnlen(m.name, sizeof(m.name)));
        scene.materials.push_back(material);
    }
    if (scene.materials.empty()) scene.materials.emplace_back();
    if (h.flags & kChsFlagCamera) {
        Camera c;
        c.eye = {h.camera[0], h.camera[1], h.camera[2]};
        c.target = {h.camera[3], h.camera[4], h.camera[5]};
        c.up = {h.camera[6], h.camera[7], h.camera[8]};
        c.fovYDegrees = h.camera[9];
        scene.cameras.push_back({"prepared", c});
    }
}

} // namespace

LoadedPreparedScene loadPreparedSceneProxy(const std::filesystem::path& file) {
    const ChsFile chs(file);
    const ChsHeader& h = chs.header();
    LoadedPreparedScene out;
    loadMetadata(chs, file, out);
    Scene& scene = out.scene;
    // One zero-area triangle from the minimum to the maximum corner: the scene's bounds (near plane, ray
    // lengths as fractions of the diagonal) equal the real scene's, and no ray can hit it.
    const glm::vec3 lo(h.boundsMin[0], h.boundsMin[1], h.boundsMin[2]), hi(h.boundsMax[0], h.boundsMax[1], h.boundsMax[2]);
    scene.positions = {lo, hi, hi};
    scene.normals.assign(3, glm::vec3(0.0f, 1.0f, 0.0f));
    scene.triangles = {glm::uvec3(0, 1, 2)};
    scene.triangleMaterials = {0};
    scene.stats.uniqueTriangles = scene.stats.instancedTriangles = h.triangleCount; // what the file holds
    scene.stats.meshCount = scene.stats.instanceCount = 1;
    out.bvh = buildBvh(scene);
    return out;
}

LoadedPreparedScene loadPreparedScene(const std::filesystem::path& file) {
    const ChsFile chs(file);
    const ChsHeader& h = chs.header();
    LoadedPreparedScene out;
    loadMetadata(chs, file, out);
    Scene& scene = out.scene;
    if (h.triangleCount >= (uint64_t(1) << 32) / 3) throw InputError(file.string() + ": too large to load in core");
    const size_t n = size_t(h.triangleCount);
    scene.positions.resize(n * 3);
    scene.normals.resize(n * 3);
    if (chs.hasTexcoords()) scene.texcoords.resize(n * 3);
    scene.triangles.resize(n);
    scene.triangleMaterials.resize(n);
    Bvh& bvh = out.bvh;
    bvh.nodes.resize(h.upperNodeCount);
    bvh.nodes.reserve(h.upperNodeCount + h.nodeCount);
    bvh.triangles.reserve(n);
    std::vector<uint8_t> seen(n, 0);
    const auto& upper = chs.upperNodes();
    for (uint32_t i = 0; i < h.upperNodeCount; ++i) {
        const ChsUpperNode& u = upper[i];
        BvhNodeGpu& dst = bvh.nodes[i];
        dst.boundsMin = {u.boundsMin[0], u.boundsMin[1], u.boundsMin[2]};
        dst.boundsMax = {u.boundsMax[0], u.boundsMax[1], u.boundsMax[2]};
        if (u.subtree == kChsNoSubtree) {
            dst.leftFirst = u.firstChild;
            dst.triCount = 0;
            continue;
        }
        // Splice the subtree in: its root replaces the upper node, the rest is appended (local k >= 1 goes to
        // base + k - 1), leaves point into the appended triangles.
        const SubtreeData d = chs.readSubtree(u.subtree);
        const uint32_t base = uint32_t(bvh.nodes.size()), triBase = uint32_t(bvh.triangles.size());
        auto rebase = [&](BvhNodeGpu node) {
            node.leftFirst = node.triCount != 0 ? node.leftFirst + triBase : base + node.leftFirst - 1;
            return node;
        };
        dst = rebase(d.nodes[0]);
        for (size_t k = 1; k < d.nodes.size(); ++k) bvh.nodes.push_back(rebase(d.nodes[k]));
        for (size_t t = 0; t < d.triangles.size(); ++t) {
            const TriangleGpu& tri = d.triangles[t];
            if (tri.originalId >= n || seen[tri.originalId]) {
                throw InputError(file.string() + ": triangle ids do not cover 0.." + std::to_string(n - 1) + " exactly once");
            }
            seen[tri.originalId] = 1;
            bvh.triangles.push_back(tri);
            const size_t id = tri.originalId, v = id * 3;
            scene.positions[v] = tri.v0, scene.positions[v + 1] = tri.v1, scene.positions[v + 2] = tri.v2;
            for (int c = 0; c < 3; ++c) {
                scene.normals[v + c] = d.normals[t * 3 + c];
                if (!d.texcoords.empty()) scene.texcoords[v + c] = d.texcoords[t * 3 + c];
            }
            scene.triangles[id] = glm::uvec3(uint32_t(v), uint32_t(v + 1), uint32_t(v + 2));
            if (tri.materialId >= scene.materials.size()) throw InputError(file.string() + ": material id out of range");
            scene.triangleMaterials[id] = tri.materialId;
        }
    }
    scene.stats.uniqueTriangles = scene.stats.instancedTriangles = n;
    scene.stats.meshCount = scene.stats.instanceCount = 1;
    bvh.stats.nodeCount = uint32_t(bvh.nodes.size());
    bvh.stats.sahCost = computeSahCost(bvh);
    bvh.stats.bytes = bvh.nodes.size() * sizeof(BvhNodeGpu) + bvh.triangles.size() * sizeof(TriangleGpu);
    for (const BvhNodeGpu& node : bvh.nodes) bvh.stats.leafCount += node.triCount != 0;
    bvh.stats.averageLeafTriangles = bvh.stats.leafCount ? double(n) / bvh.stats.leafCount : 0.0;
    return out;
}

} // namespace chcrt::outofcore

namespace chcrt::outofcore {

ChsFileSummary summarize(const ChsFile& file) {
    ChsFileSummary s;
    s.minTriangles = UINT32_MAX;
    for (const ChsSubtreeRecord& r : file.subtrees()) {
        s.minTriangles = std::min(s.minTriangles, r.triangleCount);
        s.maxHeight = std::max(s.maxHeight, r.height);
        s.subtreeBytes += r.bytes;
    }
    s.meanTriangles = double(file.header().triangleCount) / double(file.subtrees().size());
    const uint32_t levels = file.lodLevels();
    s.proxyTrianglesPerLevel.assign(levels, 0);
    s.proxiesPerLevel.assign(levels, 0);
    for (uint32_t i = 0; i < file.subtrees().size(); ++i) {
        for (uint32_t l = 1; l <= levels; ++l) {
            const ChsLodRecord& r = file.lodRecord(i, l);
            if (r.nodeCount == 0) continue;
            s.proxyBytes += r.bytes;
            ++s.proxies;
            ++s.proxiesPerLevel[l - 1];
            s.proxyTrianglesPerLevel[l - 1] += r.triangleCount;
        }
    }
    return s;
}

} // namespace chcrt::outofcore
