#pragma once
// The scene on the GPU: vertex/index buffers for rasterising the G-buffer, the BVH and its triangles as
// texture buffers for tracing (shaders/shared/bvh_layout.h), per-triangle attributes and materials for shading
// hits, and base-colour textures as one texture array. Built once per scene; read-only afterwards.
#include "renderer/bvh/bvh.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/scene/scene.h"

#include <cstdint>

namespace chcrt {

class SceneGpu {
public:
    // Requires a current GL context. Throws GlError when a buffer exceeds the texture-buffer limit.
    SceneGpu(const Scene& scene, const Bvh& bvh);

    // Binds the texture buffers and the texture array to their units (shaders/shared/render_layout.h).
    void bindForTracing() const;
    void bindForShading() const;
    // Draws all triangles in scene order (gl_PrimitiveID = original triangle id).
    void drawTriangles() const;

    uint64_t triangleCount() const { return triangleCount_; }
    uint64_t gpuBytes() const { return gpuBytes_; }

private:
    void uploadGeometry(const Scene& scene);
    void uploadAttributes(const Scene& scene);
    void uploadMaterials(const Scene& scene);

    GlVertexArray vertexArray_;
    GlBuffer vertexBuffer_;
    GlBuffer indexBuffer_;
    TextureBuffer bvhNodes_;
    TextureBuffer bvhTriangles_;
    TextureBuffer triangleAttributes_;
    TextureBuffer materials_;
    GlTexture baseColorArray_;
    uint64_t triangleCount_ = 0;
    uint64_t gpuBytes_ = 0;
};

} // namespace chcrt
