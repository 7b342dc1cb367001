// RAII deleters and creation helpers for the GL objects the renderer uses; all creation goes through DSA
// (glCreate*, glNamed*), so no helper changes a binding the caller relies on (drawFullscreenTriangle binds
// its VAO, as drawing requires).
#include "renderer/gl/gl_objects.h"

#include "renderer/core/error.h"
#include "renderer/gl/gl_internal.h"

#include <string>
#include <vector>

namespace chcrt {
namespace {

// Bytes per texel of the texture-buffer formats the renderer uses (GL 4.5 §8.9, table 8.16 subset).
size_t textureBufferTexelSize(GLenum format) {
    switch (format) {
    case GL_R8: case GL_R8UI: case GL_R8I: return 1;
    case GL_R16F: case GL_R16UI: case GL_R16I: case GL_RG8: case GL_RG8UI: return 2;
    case GL_R32F: case GL_R32UI: case GL_R32I: case GL_RG16F: case GL_RGBA8: case GL_RGBA8UI: return 4;
    case GL_RG32F: case GL_RG32UI: case GL_RG32I: case GL_RGBA16F: case GL_RGBA16UI: return 8;
    case GL_RGB32F: case GL_RGB32UI: case GL_RGB32I: return 12;
    case GL_RGBA32F: case GL_RGBA32UI: case GL_RGBA32I: return 16;
    default: throw GlError("createTextureBuffer: unsupported internal format 0x" + std::to_string(format));
    }
}

std::string framebufferStatusName(GLenum status) {
    switch (status) {
    case GL_FRAMEBUFFER_UNDEFINED: return "GL_FRAMEBUFFER_UNDEFINED";
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER: return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
    case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER: return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
    case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS: return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
    default: return "status " + std::to_string(status);
    }
}

} // namespace

void BufferTraits::destroy(GLuint id) { glDeleteBuffers(1, &id); }
void TextureTraits::destroy(GLuint id) { glDeleteTextures(1, &id); }
void FramebufferTraits::destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
void VertexArrayTraits::destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
void QueryTraits::destroy(GLuint id) { glDeleteQueries(1, &id); }

GlBuffer createBuffer(size_t bytes, const void* data, GLbitfield storageFlags) {
    // Immutable storage of size 0 is an error (GL_INVALID_VALUE); a 16-byte minimum spares callers a special
    // case for empty scenes (nothing reads past the real size).
    GLuint id = 0;
    glCreateBuffers(1, &id);
    GlBuffer buffer(id);
    if (bytes == 0) {
        glNamedBufferStorage(id, 16, nullptr, storageFlags);
    } else {
        glNamedBufferStorage(id, static_cast<GLsizeiptr>(bytes), data, storageFlags);
    }
    checkGlErrors("createBuffer");
    return buffer;
}

TextureExtent textureExtent(GLuint texture) {
    TextureExtent extent;
    if (texture == 0) return extent;
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_WIDTH, &extent.width);
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_HEIGHT, &extent.height);
    return extent;
}

GlTexture createTexture2D(int width, int height, GLenum internalFormat, int levels) {
    if (width <= 0 || height <= 0 || levels <= 0) {
        throw GlError("createTexture2D: invalid size " + std::to_string(width) + "x" + std::to_string(height) +
                      " with " + std::to_string(levels) + " levels");
    }
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    GlTexture texture(id);
    glTextureStorage2D(id, levels, internalFormat, width, height);
    // Render targets and data textures are read texel-exactly; nothing relies on filtering.
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    checkGlErrors("createTexture2D");
    return texture;
}

GlQuery createQuery(GLenum target) {
    GLuint id = 0;
    glCreateQueries(target, 1, &id);
    return GlQuery(id);
}

GlVertexArray createVertexArray() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return GlVertexArray(id);
}

TextureBuffer createTextureBuffer(const void* data, size_t bytes, GLenum internalFormat) {
    // Step 1: the size limit, checked before anything is allocated.
    const size_t texelSize = textureBufferTexelSize(internalFormat);
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    const size_t texels = bytes / texelSize;
    if (texels > static_cast<size_t>(maxTexels)) {
        throw GlError("texture buffer of " + std::to_string(texels) + " texels exceeds GL_MAX_TEXTURE_BUFFER_SIZE (" +
                      std::to_string(maxTexels) + " texels); the scene is too large for this GL implementation");
    }
    // Step 2: buffer + texture view. Updates go through glNamedBufferSubData (dynamic storage).
    TextureBuffer result;
    result.buffer = createBuffer(bytes, data, GL_DYNAMIC_STORAGE_BIT);
    result.bytes = bytes;
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &id);
    result.texture = GlTexture(id);
    glTextureBuffer(id, internalFormat, result.buffer.id());
    checkGlErrors("createTextureBuffer");
    return result;
}

GlFramebuffer createFramebuffer(const GLuint* colorTextures, int colorCount, GLuint depthTexture) {
    GLint maxDrawBuffers = 0;
    glGetIntegerv(GL_MAX_DRAW_BUFFERS, &maxDrawBuffers);
    if (colorCount < 0 || colorCount > maxDrawBuffers) {
        throw GlError("createFramebuffer: " + std::to_string(colorCount) + " colour attachments requested, " +
                      "GL_MAX_DRAW_BUFFERS is " + std::to_string(maxDrawBuffers));
    }
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    GlFramebuffer framebuffer(id);
    std::vector<GLenum> drawBuffers;
    for (int i = 0; i < colorCount; ++i) {
        const GLenum attachment = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i);
        glNamedFramebufferTexture(id, attachment, colorTextures[i], 0);
        drawBuffers.push_back(attachment);
    }
    if (depthTexture != 0) {
        // Packed depth-stencil formats must be attached to both points at once.
        GLint format = 0;
        glGetTextureLevelParameteriv(depthTexture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
        const bool hasStencil = format == GL_DEPTH24_STENCIL8 || format == GL_DEPTH32F_STENCIL8;
        glNamedFramebufferTexture(id, hasStencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT,
                                  depthTexture, 0);
    }
    if (colorCount > 0) {
        glNamedFramebufferDrawBuffers(id, colorCount, drawBuffers.data());
        glNamedFramebufferReadBuffer(id, GL_COLOR_ATTACHMENT0);
    } else {
        glNamedFramebufferDrawBuffer(id, GL_NONE);
        glNamedFramebufferReadBuffer(id, GL_NONE);
    }
    const GLenum status = glCheckNamedFramebufferStatus(id, GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        throw GlError("framebuffer incomplete: " + framebufferStatusName(status) + " (" +
                      std::to_string(colorCount) + " colour attachments" + (depthTexture != 0 ? " + depth)" : ")"));
    }
    checkGlErrors("createFramebuffer");
    return framebuffer;
}

namespace {
// Core profile draws need a bound VAO even without attributes. One empty VAO per context: VAOs are not shared
// between contexts, so the cached name is dropped whenever loadGlFunctions() has run again (every new context,
// including a GLFW window, loads the table first). The old name died with its context and is deliberately not
// deleted. Single-threaded use only, like the one-context-per-process model.
void bindEmptyVertexArray() {
    static GLuint vao = 0;
    static unsigned vaoGeneration = 0;
    if (vao == 0 || vaoGeneration != detail::glLoadGeneration()) {
        glCreateVertexArrays(1, &vao);
        vaoGeneration = detail::glLoadGeneration();
    }
    glBindVertexArray(vao);
}
} // namespace

void drawAttributelessIndirect(GLenum mode) {
    bindEmptyVertexArray();
    glDrawArraysIndirect(mode, nullptr);
}

void drawAttributeless(GLenum mode, GLsizei vertexCount) {
    bindEmptyVertexArray();
    glDrawArrays(mode, 0, vertexCount);
}

void drawFullscreenTriangle() {
    drawAttributeless(GL_TRIANGLES, 3);
}

GpuTimer::GpuTimer() : query_(createQuery(GL_TIME_ELAPSED)) {}

void GpuTimer::begin() { glBeginQuery(GL_TIME_ELAPSED, query_.id()); }

void GpuTimer::end() { glEndQuery(GL_TIME_ELAPSED); }

double GpuTimer::milliseconds() {
    GLuint64 nanoseconds = 0;
    glGetQueryObjectui64v(query_.id(), GL_QUERY_RESULT, &nanoseconds);
    return static_cast<double>(nanoseconds) * 1e-6;
}

} // namespace chcrt
