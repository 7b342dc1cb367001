#pragma once
// Reading a prepared scene (.chs, chs_format.h). Opening validates the header, its checksum, the version, the
// file size and the metadata (upper hierarchy, directory, materials) with its checksum; a subtree's checksum
// is verified on its first read, and again after the file changed under the open descriptor (its size or times). Every problem is an InputError with a one-line message naming the file.
//
// Reads use explicit positional I/O (pread), not mmap: a subtree is decoded into its own buffers anyway
// (rebasing for the GPU needs a copy), explicit reads keep the process's memory exactly what the host cache
// holds (mapped file pages would count towards RSS and their eviction is up to the kernel), and an I/O error
// becomes an exception instead of SIGBUS on a truncated file.
#include "renderer/core/uninitialized_vector.h"
#include "renderer/outofcore/chs_format.h"
#include "renderer/scene/scene.h"

#include <filesystem>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <unordered_set>
#include <vector>

namespace chcrt::outofcore {

// One decoded subtree: nodes and triangles with local indices, as stored.
// Uninitialised vectors: a read fills them at once (core/uninitialized_vector.h says why).
// From a compact file (version 3, compact_subtree.h) it also holds the blob's GPU payload as stored (compactNodes,
// compactTriangles, vertices: what the GPU cache uploads); a read for a GPU upload alone (attributes false) fills only
// those, a whole read also the materials, normals and texture coordinates, and a decoding read (ChsFile::readSubtree's
// `decode`) also fills nodes (with the quantized boxes the traversal uses) and triangles.
struct SubtreeData {
    UninitializedVector<BvhNodeGpu> nodes;
    UninitializedVector<TriangleGpu> triangles;
    UninitializedVector<glm::vec3> normals;   // 3 per triangle
    UninitializedVector<glm::vec2> texcoords; // 3 per triangle, or empty
    UninitializedVector<glm::uvec4> compactNodes;     // compact files: node texels (shared/bvh_layout.h)
    UninitializedVector<glm::uvec4> compactTriangles; // compact files: triangle texels
    UninitializedVector<glm::vec3> vertices;          // compact files: the subtree's distinct vertices
    UninitializedVector<uint32_t> materials;          // compact files, whole reads: material id per triangle
    bool attributes = true; // normals and texcoords were read (false: read for a GPU upload alone, both empty)
    bool compact() const { return !compactNodes.empty(); }
    // Triangles of either layout (a compact whole read from the host store is not decoded: primary_resolve.h).
    size_t triangleCount() const { return compact() ? compactTriangles.size() : triangles.size(); }
    size_t nodeCount() const { return compact() ? compactNodes.size() - (CHCRT_COMPACT_ROOT_TEXELS - 1) : nodes.size(); }
    uint32_t originalId(size_t k) const { return compact() ? compactTriangles[k].w : triangles[k].originalId; }
    TriangleGpu triangle(size_t k) const {
        if (!compact()) return triangles[k];
        const glm::uvec4& t = compactTriangles[k];
        return {vertices[t.x], t.w, vertices[t.y], materials.empty() ? 0u : materials[k], vertices[t.z], 0u};
    }
    // The bytes read from the file for it.
    uint64_t readBytes() const {
        return (compact() ? 0 : nodes.size() * sizeof(BvhNodeGpu) + triangles.size() * sizeof(TriangleGpu)) +
               normals.size() * sizeof(glm::vec3) + texcoords.size() * sizeof(glm::vec2) +
               compactNodes.size() * sizeof(glm::uvec4) + compactTriangles.size() * sizeof(glm::uvec4) +
               vertices.size() * sizeof(glm::vec3) + materials.size() * sizeof(uint32_t);
    }
    // The memory it holds (capacities: buffers reused for a smaller subtree keep their size).
    uint64_t bytes() const {
        return nodes.capacity() * sizeof(BvhNodeGpu) + triangles.capacity() * sizeof(TriangleGpu) +
               normals.capacity() * sizeof(glm::vec3) + texcoords.capacity() * sizeof(glm::vec2) +
               compactNodes.capacity() * sizeof(glm::uvec4) + compactTriangles.capacity() * sizeof(glm::uvec4) +
               vertices.capacity() * sizeof(glm::vec3) + materials.capacity() * sizeof(uint32_t);
    }
};

class ChsFile {
public:
    // Throws InputError for a missing, truncated, corrupted or version-mismatched file.
    explicit ChsFile(const std::filesystem::path& file);
    ~ChsFile();
    ChsFile(const ChsFile&) = delete;
    ChsFile& operator=(const ChsFile&) = delete;

    const ChsHeader& header() const { return header_; }
    const std::vector<ChsUpperNode>& upperNodes() const { return upper_; }
    const std::vector<ChsSubtreeRecord>& subtrees() const { return subtrees_; }
    const std::vector<ChsMaterialRecord>& materials() const { return materials_; }
    const std::string& source() const { return source_; } // generator spec or file the scene was prepared from
    const std::filesystem::path& path() const { return path_; }
    bool hasTexcoords() const { return (header_.flags & kChsFlagTexcoords) != 0; }
    // Compact subtrees (version 3, compact_subtree.h): the distinct vertices of subtree `index` at `level` (0 = the
    // subtree, >= 1 its proxy), and the most any subtree / any proxy has (the GPU cache's slot sizes).
    bool compact() const { return (header_.flags & kChsFlagCompact) != 0; }
    uint32_t vertexCount(uint32_t index, uint32_t level = 0) const;
    uint32_t maxSubtreeVertices() const { return maxSubtreeVertices_; }
    uint32_t maxProxyVertices() const { return maxProxyVertices_; }
    // LOD proxies (version 2, lod_proxies.h): levels per subtree (0 = none), the directory's header, and the record
    // of one (subtree, level >= 1); a record with nodeCount 0 holds no proxy. lodRecord throws InputError out of range.
    uint32_t lodLevels() const { return (header_.flags & kChsFlagLod) ? lod_.levels : 0u; }
    const ChsLodHeader& lodHeader() const { return lod_; }
    const ChsLodRecord& lodRecord(uint32_t subtree, uint32_t level) const;
    AreaLight light() const;

    // Reads and verifies subtree `index` (thread-safe: pread). Throws InputError on a checksum mismatch or
    // out-of-range local indices.
    SubtreeData readSubtree(uint32_t index) const;
    // Level `level` of subtree `index`: 0 = the subtree, >= 1 its LOD proxy (same layout; InputError when the file
    // holds none at that level).
    SubtreeData readSubtree(uint32_t index, uint32_t level) const;
    // The same into `into`, reusing the memory of its vectors: a read into buffers whose capacity suffices
    // allocates nothing and touches no fresh page (subtree_store.h recycles the buffers of evicted subtrees).
    // `attributes` false: nodes and triangles only when the blob was verified before in the file's current state
    // (its checksum covers the whole blob); a first read always reads and verifies everything.
    // `decode` false (the host store): a compact blob stays compact (nodes and triangles empty; SubtreeData::triangle).
    void readSubtree(uint32_t index, uint32_t level, SubtreeData& into, bool attributes = true, bool decode = true) const;
    // Triangles `locals` of subtree `index` (level 0) into triangles[i] and their 3 vertex normals each into
    // normals[3i..3i+2], without the rest of the blob: only from a blob verified in the file's current state (false
    // otherwise, and for an index out of range; then read it whole).
    bool readTriangles(uint32_t index, std::span<const uint32_t> locals, TriangleGpu* triangles,
                       glm::vec3* normals) const;
    // Reads one node (local index) of subtree `index` without the rest of the blob (thread-safe: pread), e.g.
    // its root and the root's children for the culling hierarchy's tighter bounds (CHC+RT §5.1). Not
    // checksummed: only boxes and counts are used; throws InputError for an out-of-range index.
    BvhNodeGpu readSubtreeNode(uint32_t index, uint32_t localNode) const;

private:
    void validate(); // header, sizes, metadata and structure; throws InputError
    void readBlob(uint64_t offset, uint32_t nodeCount, uint32_t triangleCount, uint32_t vertexCount, uint64_t checksum,
                  const std::string& blob, SubtreeData& d, bool attributes, bool decode) const;
    void readCompactBlob(uint64_t offset, uint32_t nodeCount, uint32_t triangleCount, uint32_t vertexCount,
                         uint64_t checksum, const std::string& blob, SubtreeData& d, bool attributes, bool decode) const;
    // What identifies the file's content for re-reads: a blob whose checksum matched is not summed again while
    // this stays the same (size, modification and status-change times of the open descriptor).
    struct FileState {
        uint64_t size = 0;
        int64_t modifiedNs = 0, changedNs = 0;
        bool operator==(const FileState&) const = default;
    };
    FileState fileState() const; // throws InputError when fstat fails
    bool blobVerified(uint64_t offset, const FileState& state) const;
    void markVerified(uint64_t offset, const FileState& state) const;
    std::filesystem::path path_;
    int fd_ = -1;
    ChsHeader header_{};
    std::vector<ChsUpperNode> upper_;
    std::vector<ChsSubtreeRecord> subtrees_;
    std::vector<ChsMaterialRecord> materials_;
    std::string source_;
    ChsLodHeader lod_{};
    std::vector<ChsLodRecord> lodRecords_; // lod_.levels per subtree, directory order
    std::vector<uint32_t> subtreeVertices_, lodVertices_; // compact files: per record, from its byte count
    uint32_t maxSubtreeVertices_ = 0, maxProxyVertices_ = 0;
    mutable std::mutex verifiedMutex_;     // reads come from the frame's thread and the prefetch thread
    mutable FileState verifiedState_;
    mutable std::unordered_set<uint64_t> verifiedBlobs_; // offsets of blobs whose checksum matched in verifiedState_
};

// Loads a whole prepared scene in core (when it fits): a Scene (3 unshared vertices per triangle, triangle i =
// original id i) and a Bvh made of the upper hierarchy with every subtree spliced in, so that traced hits
// equal those of the scene it was prepared from. Throws InputError when the triangle ids do not cover
// 0..N-1 exactly once.
struct LoadedPreparedScene {
    Scene scene;
    Bvh bvh;
    AreaLight light;
    std::string source;
};
LoadedPreparedScene loadPreparedScene(const std::filesystem::path& file);
// The scene of a prepared file WITHOUT its geometry, for rendering out of core (CHC+RT §5.4) when the scene does
// not fit: materials, light, stored camera, source spec, and a single zero-area triangle spanning the file's
// bounds (so bounds-derived settings match the real scene and nothing can be hit). Every hit then comes from
// the out-of-core tracer. Reads only the metadata.
LoadedPreparedScene loadPreparedSceneProxy(const std::filesystem::path& file);

// Estimated bytes of loadPreparedScene's result plus the renderer's GPU copies for a triangle count (used to
// decide whether an out-of-core scene can also be loaded in core for reference runs).
inline uint64_t estimatedInCoreBytes(uint64_t triangles) { return triangles * 400; }

// Whether a --scene argument names a prepared scene (by its .chs extension).
bool isPreparedScenePath(const std::string& scene);

} // namespace chcrt::outofcore

namespace chcrt::outofcore {

// Statistics of a prepared file for `chcrt info`.
struct ChsFileSummary {
    uint32_t minTriangles = 0;
    double meanTriangles = 0.0;
    uint32_t maxHeight = 0;
    uint64_t subtreeBytes = 0;
    uint64_t proxyBytes = 0;    // LOD proxies (0 without)
    uint64_t proxies = 0;       // kept proxy levels
    std::vector<uint64_t> proxyTrianglesPerLevel; // per level 1 ... lodLevels(): triangles of its kept proxies
    std::vector<uint64_t> proxiesPerLevel;        // per level: subtrees with a proxy at that level
};
ChsFileSummary summarize(const ChsFile& file);

} // namespace chcrt::outofcore
