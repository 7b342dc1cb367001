#pragma once
// Writing a prepared scene (.chs, chs_format.h) chunk by chunk: each chunk's BVH is cut into termination
// subtrees (CHC+RT §5.2: topmost nodes within the height and triangle limits) which are written at once; the
// chunk keeps only its upper nodes in memory. finish() joins the chunks under a top-level SAH tree over their
// root boxes, writes the metadata and the header, and renames the temp file into place, so an interrupted
// prepare never leaves a file that looks valid; the temp file goes with an error (destructor) and with SIGINT,
// SIGTERM or SIGHUP (RemoveOnSignal), and a stale one from a killed run is overwritten by the next.
#include "renderer/core/signal_cleanup.h"
#include "renderer/outofcore/chs_format.h"
#include "renderer/outofcore/compact_subtree.h"
#include "renderer/scene/scene.h"

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace chcrt::outofcore {

struct SubtreeBlob; // one termination subtree as written (chs_writer.cpp)

struct ChsWriterOptions {
    uint32_t subtreeTriangles = 1u << 16;
    uint32_t subtreeHeight = 24;
    uint32_t lodLevels = 0; // LOD proxy levels per subtree (lod_proxies.h); 0 = none
    // Blobs in the compact layout (version 3, compact_subtree.h); false: the full layout of versions 1 (no proxies)
    // and 2, byte for byte as those versions were written.
    bool compact = true;
};

struct ChsSceneInfo {
    std::string source;
    std::vector<Material> materials;
    AreaLight light;
    bool hasCamera = false;
    Camera camera;
    bool texcoords = false;
};

class ChsWriter {
public:
    // Creates "<file>.tmp" next to the target. Throws InputError when it cannot be created or an option is 0.
    ChsWriter(const std::filesystem::path& file, const ChsWriterOptions& options);
    ~ChsWriter(); // removes the temp file unless finish() succeeded
    ChsWriter(const ChsWriter&) = delete;
    ChsWriter& operator=(const ChsWriter&) = delete;

    // Writes one chunk: `bvh` built over `scene`; triangle original ids are offset by `idOffset`, positions
    // (and the boxes, recomputed from them) are moved by `translation`.
    void addChunk(const Scene& scene, const Bvh& bvh, uint64_t idOffset, const glm::vec3& translation = glm::vec3(0.0f));

    // Writes the metadata and header and renames the file into place. Returns the file size.
    uint64_t finish(const ChsSceneInfo& info);

    uint64_t triangleCount() const { return triangles_; }
    uint32_t subtreeCount() const { return uint32_t(records_.size()); }
    uint64_t subtreeBytes() const { return subtreeBytes_; } // all subtree blobs
    uint64_t proxyBytes() const { return proxyBytes_; }     // all LOD proxy blobs
    uint64_t proxyCount() const { return proxyCount_; }     // kept proxy levels
    uint64_t vertexCount() const { return vertices_; }      // the compact subtree blobs' distinct vertices

private:
    struct Chunk {
        std::vector<ChsUpperNode> nodes; // root = 0; termination roots carry their subtree index
    };
    void write(const void* data, size_t bytes);
    // Checks a chunk against the earlier ones (texture coordinates) and the 32-bit triangle ids.
    void checkChunk(const Scene& scene, uint64_t idOffset);
    // Appends the subtree and its directory record, then its LOD proxies; returns its index in the directory.
    uint32_t writeSubtree(const SubtreeBlob& blob, uint32_t height);
    // Appends a blob (nodes, triangles, normals, texture coordinates); returns its checksum.
    uint64_t writeBlob(const std::vector<BvhNodeGpu>& nodes, const std::vector<TriangleGpu>& triangles,
                       const std::vector<glm::vec3>& normals, const std::vector<glm::vec2>& texcoords);
    void writeProxies(const SubtreeBlob& blob);

    std::filesystem::path file_, temp_;
    RemoveOnSignal removeTempOnSignal_;
    ChsWriterOptions options_;
    std::FILE* out_ = nullptr;
    uint64_t offset_ = 0;
    uint64_t triangles_ = 0;
    uint64_t nodes_ = 0;
    uint32_t maxNodes_ = 0, maxTriangles_ = 0;
    uint64_t vertices_ = 0, lastBlobVertices_ = 0;
    CompactSubtree compact_; // the blob being written, reused
    bool texcoords_ = false;
    bool texcoordsKnown_ = false;
    std::vector<ChsSubtreeRecord> records_;
    std::vector<ChsLodRecord> lodRecords_; // options_.lodLevels per subtree, in the order of records_
    uint64_t subtreeBytes_ = 0, proxyBytes_ = 0, proxyCount_ = 0;
    uint32_t maxProxyNodes_ = 0, maxProxyTriangles_ = 0;
    std::vector<Chunk> chunks_;
    bool finished_ = false;
};

} // namespace chcrt::outofcore
