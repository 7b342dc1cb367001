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
    // Requires a current GL context (the drawing one or one sharing its objects). Throws GlError when a buffer exceeds the texture-buffer limit.
    SceneGpu(const Scene& scene, const Bvh& bvh);

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
    TextureBuffer bvhTriangles_;
    TextureBuffer triangleAttributes_;
    TextureBuffer triangleNormals_; // vertex normals per original id (traced G-buffer)
    TextureBuffer materials_;
    GlTexture baseColorArray_;
    uint64_t triangleCount_ = 0;
    uint32_t baseColorSide_ = 1;
    uint64_t gpuBytes_ = 0;
};

} // namespace chcrt
