#pragma once
// Primary visibility of a scene that is not in core (issue #5; CHC+RT §5.4, the "Prim" column of Table 3):
// primary rays are traced by the OutOfCoreTracer, and their hits resolved into the renderer's G-buffer. The
// in-core resolve (raster/gbuffer_from_hits.frag.glsl) reads per-triangle buffers indexed by original id over
// the whole scene, which cannot exist out of core. Here the tracer records, per pixel, the termination subtree
// that produced the final hit (ChcrtTracer's "subtrees" debug image: the subtree shader stores it whenever a
// ray's hit changes); the host then looks the hit triangle up in that subtree (host store: decoded subtrees
// with the file's vertex normals and the triangles' material ids), writes per-pixel shading normal, geometric
// normal and albedo images, and outofcore/gbuffer_from_pixel_attributes.frag.glsl writes the G-buffer with
// the same orientation rule as the in-core pass. Nothing here is indexed by triangle id over the scene, and
// the shared traversal shaders are unchanged.
#include "culling/outofcore/out_of_core_tracer.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"
#include "renderer/render/frame_targets.h"
#include "renderer/scene/scene.h"

#include <glm/glm.hpp>

#include <unordered_map>
#include <vector>

namespace chcrt::outofcore {

struct PrimaryResolveStats {
    uint64_t hitPixels = 0;
    uint64_t subtreesRead = 0;    // subtrees looked up this frame (host store gets)
    uint64_t unresolvedPixels = 0; // hits whose triangle was not found (never expected; shaded with the geometric normal 0)
    uint64_t subtreesIndexed = 0;  // of subtreesRead: looked up through a dense id table
    uint64_t subtreesScanned = 0;  // of subtreesRead: ids too spread for a table, the subtree was scanned
    uint64_t subtreesByTriangles = 0; // of subtreesRead: not in the host store, only its hit triangles read
    uint64_t trianglesRead = 0;       // by those: their distinct hit triangles, read from the file
    double hostMs = 0.0;           // read-back, lookup and upload
};

class PrimaryResolve {
public:
    // Turns on the tracer's per-pixel subtree recording for primary rays. Needs a current GL context.
    // `denseSpanFactor`: subtrees whose original ids span at most this many times their triangle count get a dense
    // id table (0: none, every subtree is scanned; tests use it to cover both lookups).
    static constexpr uint64_t kDefaultDenseSpanFactor = 4;
    explicit PrimaryResolve(OutOfCoreTracer& tracer, uint64_t denseSpanFactor = kDefaultDenseSpanFactor);
    ~PrimaryResolve();
    PrimaryResolve(const PrimaryResolve&) = delete;
    PrimaryResolve& operator=(const PrimaryResolve&) = delete;

    // Writes targets.gbuffer from ray set 0 and hit set 0, which must hold the primary rays just traced by
    // the tracer. `nearPlane` as the renderer's (camera_math.h, nearPlaneFor).
    void resolve(const Camera& camera, const FrameTargets& targets, float nearPlane);
    const PrimaryResolveStats& lastStats() const { return stats_; }
    // Per-pixel unit geometric normals of the last resolve (RGBA32F, frame size; 0 before the first), for
    // secondary ray generation (Renderer::setOutOfCorePrimary).
    GLuint geometricNormalTexture() const { return geometric_.id(); }
    // Per pixel of the last resolve: 1 + the termination subtree (file directory index) that produced the
    // primary hit, 0 = no hit (GL row order, bottom row first; empty before the first). The viewer's residency
    // view colours pixels by it (app/viewer/README.md).
    const std::vector<uint32_t>& lastPixelSubtrees() const { return pixelSubtrees_; }

private:
    // Original id -> index in the subtree, for subtrees whose ids span at most denseSpanFactor_ × their triangles.
    struct DenseIdIndex {
        uint32_t first = 0;
        std::vector<uint32_t> localOf; // [id - first]; UINT32_MAX = not in the subtree; empty = ids not compact
        uint64_t lastUse = 0;
        uint32_t find(uint32_t id) const; // UINT32_MAX when absent
    };
    // Kept across frames, least recently used dropped first; memory outside --host-cache-mb, so bounded here.
    static constexpr uint64_t kDenseBudgetBytes = uint64_t(96) << 20;
    const DenseIdIndex* denseIndexFor(uint64_t key, const SubtreeData& data); // key: level << 32 | subtree
    bool resolveByTriangles(uint32_t subtree, const std::vector<uint32_t>& pixels, std::vector<TriangleGpu>& triangles,
                            std::vector<glm::vec3>& normals, std::vector<uint32_t>& triangleOfPixel);
    std::vector<uint32_t> pixelTriangles_;         // the frame's hit triangle image
    std::vector<uint32_t> hitIndices_, hitLocals_; // resolveByTriangles: a subtree's distinct hit triangles

    OutOfCoreTracer& tracer_;
    uint64_t denseSpanFactor_;
    std::unordered_map<uint64_t, DenseIdIndex> denseIndex_;
    uint64_t denseBytes_ = 0, useClock_ = 0;
    std::vector<glm::vec3> albedos_; // per material (base colour factor; v1 files keep no textures)
    ShaderProgram program_;
    GlTexture shading_, geometric_, albedo_;
    int width_ = 0, height_ = 0;
    std::vector<uint32_t> pixelSubtrees_;
    std::vector<glm::uvec4> hits_;                                 // read-back hits of the last resolve
    std::vector<glm::vec4> shadingRgba_, geometricRgba_, albedoRgba_; // uploaded per-pixel attributes
    PrimaryResolveStats stats_;
};

} // namespace chcrt::outofcore
