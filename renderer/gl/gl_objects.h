#pragma once
// Move-only RAII owners of GL objects, and helpers for the few kinds of resources the renderer makes.
#include "renderer/gl/gl.h"

#include <cstddef>
#include <utility>

namespace chcrt {

// GL object name + deleter. T provides static void destroy(GLuint).
template <typename Traits>
class GlHandle {
public:
    GlHandle() = default;
    explicit GlHandle(GLuint id) : id_(id) {}
    ~GlHandle() { reset(); }
    GlHandle(GlHandle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    GlHandle& operator=(GlHandle&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = std::exchange(o.id_, 0);
        }
        return *this;
    }
    GlHandle(const GlHandle&) = delete;
    GlHandle& operator=(const GlHandle&) = delete;
    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset() {
        if (id_ != 0) {
            Traits::destroy(id_);
            id_ = 0;
        }
    }

private:
    GLuint id_ = 0;
};

struct BufferTraits { static void destroy(GLuint id); };
struct TextureTraits { static void destroy(GLuint id); };
struct FramebufferTraits { static void destroy(GLuint id); };
struct VertexArrayTraits { static void destroy(GLuint id); };
struct QueryTraits { static void destroy(GLuint id); };
using GlBuffer = GlHandle<BufferTraits>;
using GlTexture = GlHandle<TextureTraits>;
using GlFramebuffer = GlHandle<FramebufferTraits>;
using GlVertexArray = GlHandle<VertexArrayTraits>;
using GlQuery = GlHandle<QueryTraits>;

GlBuffer createBuffer(size_t bytes, const void* data, GLbitfield storageFlags = GL_DYNAMIC_STORAGE_BIT);
GlTexture createTexture2D(int width, int height, GLenum internalFormat, int levels = 1);
// The size of a 2D texture's level 0; 0 x 0 for no texture (id 0).
struct TextureExtent {
    int width = 0, height = 0;
    bool operator==(const TextureExtent&) const = default;
};
TextureExtent textureExtent(GLuint texture);
GlQuery createQuery(GLenum target);
GlVertexArray createVertexArray();

// A texture buffer view (TBO) of a buffer: the renderer reads scene data through these (~10x faster than SSBOs
// on llvmpipe). Throws GlError when `bytes / texelSize` exceeds GL_MAX_TEXTURE_BUFFER_SIZE.
struct TextureBuffer {
    GlBuffer buffer;
    GlTexture texture;
    size_t bytes = 0;
};
TextureBuffer createTextureBuffer(const void* data, size_t bytes, GLenum internalFormat);

// Framebuffer with the given colour attachments (in order, as draw buffers 0..n-1) and an optional depth
// attachment; throws GlError when incomplete.
GlFramebuffer createFramebuffer(const GLuint* colorTextures, int colorCount, GLuint depthTexture = 0);

// Draws one triangle covering the viewport (vertex shader "render/fullscreen.vert.glsl" derives positions from
// gl_VertexID); binds an empty VAO owned by the current thread's context.
void drawFullscreenTriangle();
// Draws `vertexCount` vertices as primitives `mode` with no vertex attributes (the vertex shader derives everything
// from gl_VertexID), with the same empty VAO.
void drawAttributeless(GLenum mode, GLsizei vertexCount);
// The same with the vertex count of the indirect command at offset 0 of the bound GL_DRAW_INDIRECT_BUFFER.
void drawAttributelessIndirect(GLenum mode);

// GPU time of a scope via GL_TIME_ELAPSED (blocking read; used only where timings are requested).
class GpuTimer {
public:
    GpuTimer();
    void begin();
    void end();
    double milliseconds(); // waits for the result
private:
    GlQuery query_;
};

} // namespace chcrt
