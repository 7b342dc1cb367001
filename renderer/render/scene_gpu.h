#pragma once
// The scene on the GPU: vertex/index buffers for rasterising the G-buffer, the BVH and its triangles as
// texture buffers for tracing (shaders/shared/bvh_layout.h), per-triangle attributes and materials for shading
// hits, and base-colour textures as one texture array. Built once per scene; read-only afterwards. It may be built
// on a context that shares objects with the drawing one (the viewer uploads on a worker thread): everything but the
// vertex array is a shared object, and the vertex array is made on the first draw.
#include "renderer/bvh/bvh.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/scene/scene.h"

#include <cstdint>
#include <vector>

namespace chcrt {

class SceneGpu {
public:
    // Requires a current GL context (the drawing one or one sharing its objects). Each per-triangle array
    // (BVH-ordered triangles, attributes, vertex normals) that exceeds one texture buffer is split into parts
    // (shaders/shared/render_layout.h, "Per-triangle data beyond one texture buffer"), up to
    // CHCRT_MAX_TRIANGLE_BUFFERS; a split raises the process-wide CHCRT_TRIANGLE_BUFFERS define
    // (setProcessShaderDefine) so that programs compiled afterwards read every part: make the tracers after the
    // scene. `maxBufferTexels` (0: GL_MAX_TEXTURE_BUFFER_SIZE) caps a part's size; tests lower it to split small
    // scenes. Throws GlError when the scene needs more parts, or its BVH nodes more than one buffer.
    SceneGpu(const Scene& scene, const Bvh& bvh, uint64_t maxBufferTexels = 0);

    // Binds the texture buffers and the texture array to their units (shaders/shared/render_layout.h).
    void bindForTracing() const;
    void bindForShading() const;
    // Draws the triangles of every cluster whose box is not entirely outside the frustum of clipFromWorld
    // (reversed infinite Z, so there is no far plane). Triangles are stored in BVH order, clusters are BVH subtrees
    // (contiguous ranges); the G-buffer shader recovers the original id from the cluster's first BVH-order triangle
    // (a per-draw attribute through baseInstance) plus gl_PrimitiveID. Returns the number of triangles drawn.
    // Culling whole clusters that cannot produce fragments leaves the G-buffer bit-identical (tested).
    uint64_t drawTriangles(const glm::mat4& clipFromWorld, bool frustumCulling = true);
    size_t clusterCount() const { return clusters_.size(); }

    uint64_t triangleCount() const { return triangleCount_; }
    // Side of the base-colour texture array's level 0 in texels (mip selection of traced hits).
    uint32_t baseColorSide() const { return baseColorSide_; }
    uint64_t gpuBytes() const { return gpuBytes_; }
    // Texture buffers each per-triangle array takes (1 unless the scene exceeds one buffer).
    int triangleBufferCount() const { return int(bvhTriangles_.size()); }
    // GPU bytes a scene of `triangles` triangles, `vertices` vertices and `nodes` BVH nodes takes here (buffers
    // only; textures and frame targets come on top): what --load-in-core auto weighs against GPU memory.
    static uint64_t estimatedBytes(uint64_t triangles, uint64_t vertices, uint64_t nodes);

private:
    struct Cluster {
        Aabb bounds;
        uint32_t firstTriangle = 0; // BVH order
        uint32_t triangleCount = 0;
    };
    void uploadGeometry(const Scene& scene, const Bvh& bvh);
    void createVertexArrayForDrawing();
    void buildClusters(const Bvh& bvh);
    void uploadAttributes(const Scene& scene);
    void uploadMaterials(const Scene& scene);

    GlVertexArray vertexArray_; // of the drawing context, made on the first draw
    GlBuffer vertexBuffer_;
    GlBuffer indexBuffer_;       // BVH triangle order
    GlBuffer clusterFirstBuffer_; // per cluster: first BVH-order triangle (instanced attribute, divisor 1)
    GlBuffer indirectBuffer_;     // DrawElementsIndirectCommand per visible cluster
    std::vector<Cluster> clusters_;
    TextureBuffer bvhNodes_;
    // Per-triangle arrays, each in one or more parts (units in shaders/shared/render_layout.h).
    std::vector<TextureBuffer> bvhTriangles_;
    std::vector<TextureBuffer> triangleAttributes_;
    std::vector<TextureBuffer> triangleNormals_; // vertex normals per original id (traced G-buffer)
    TextureBuffer materials_;
    GlTexture baseColorArray_;
    uint64_t triangleCount_ = 0;
    uint32_t baseColorSide_ = 1;
    uint64_t gpuBytes_ = 0;
    uint64_t maxBufferTexels_ = 0; // a per-triangle buffer part's size limit
};

} // namespace chcrt
