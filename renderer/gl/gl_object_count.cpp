// Counting wrappers in the GL function table (gl_object_count.h).
#include "renderer/gl/gl_object_count.h"

#include "renderer/gl/gl.h"

#include <array>
#include <atomic>

namespace chcrt {
namespace {

enum Kind { Buffers, Textures, Framebuffers, Renderbuffers, VertexArrays, Queries, Samplers, Programs, Shaders, Syncs, kKinds };

std::array<std::atomic<int64_t>, kKinds> gLive{};

void add(Kind kind, int64_t n) { gLive[kind].fetch_add(n, std::memory_order_relaxed); }

int64_t nonZero(GLsizei n, const GLuint* names) {
    int64_t count = 0;
    for (GLsizei i = 0; names != nullptr && i < n; ++i) count += names[i] != 0;
    return count;
}

// The driver's functions, called by the wrappers (refreshed by every loadGlFunctions()).
struct Real {
    PFNGLGENBUFFERSPROC genBuffers;
    PFNGLCREATEBUFFERSPROC createBuffers;
    PFNGLDELETEBUFFERSPROC deleteBuffers;
    PFNGLGENTEXTURESPROC genTextures;
    PFNGLCREATETEXTURESPROC createTextures;
    PFNGLDELETETEXTURESPROC deleteTextures;
    PFNGLGENFRAMEBUFFERSPROC genFramebuffers;
    PFNGLCREATEFRAMEBUFFERSPROC createFramebuffers;
    PFNGLDELETEFRAMEBUFFERSPROC deleteFramebuffers;
    PFNGLGENRENDERBUFFERSPROC genRenderbuffers;
    PFNGLCREATERENDERBUFFERSPROC createRenderbuffers;
    PFNGLDELETERENDERBUFFERSPROC deleteRenderbuffers;
    PFNGLGENVERTEXARRAYSPROC genVertexArrays;
    PFNGLCREATEVERTEXARRAYSPROC createVertexArrays;
    PFNGLDELETEVERTEXARRAYSPROC deleteVertexArrays;
    PFNGLGENQUERIESPROC genQueries;
    PFNGLCREATEQUERIESPROC createQueries;
    PFNGLDELETEQUERIESPROC deleteQueries;
    PFNGLGENSAMPLERSPROC genSamplers;
    PFNGLCREATESAMPLERSPROC createSamplers;
    PFNGLDELETESAMPLERSPROC deleteSamplers;
    PFNGLCREATEPROGRAMPROC createProgram;
    PFNGLCREATESHADERPROGRAMVPROC createShaderProgramv;
    PFNGLDELETEPROGRAMPROC deleteProgram;
    PFNGLCREATESHADERPROC createShader;
    PFNGLDELETESHADERPROC deleteShader;
    PFNGLFENCESYNCPROC fenceSync;
    PFNGLDELETESYNCPROC deleteSync;
};
Real gReal{};

// glGen*/glCreate*(n, names) and glDelete*(n, names) of one kind.
#define CHCRT_COUNT_NAMES(KIND, GEN, DELETE)                                                                        \
    void APIENTRY counted_##GEN(GLsizei n, GLuint* names) {                                                            \
        gReal.GEN(n, names);                                                                                           \
        add(KIND, nonZero(n, names));                                                                                  \
    }                                                                                                                  \
    void APIENTRY counted_##DELETE(GLsizei n, const GLuint* names) {                                                   \
        add(KIND, -nonZero(n, names));                                                                                 \
        gReal.DELETE(n, names);                                                                                        \
    }
CHCRT_COUNT_NAMES(Buffers, genBuffers, deleteBuffers)
CHCRT_COUNT_NAMES(Framebuffers, genFramebuffers, deleteFramebuffers)
CHCRT_COUNT_NAMES(Renderbuffers, genRenderbuffers, deleteRenderbuffers)
CHCRT_COUNT_NAMES(VertexArrays, genVertexArrays, deleteVertexArrays)
CHCRT_COUNT_NAMES(Samplers, genSamplers, deleteSamplers)
CHCRT_COUNT_NAMES(Textures, genTextures, deleteTextures)
CHCRT_COUNT_NAMES(Queries, genQueries, deleteQueries)
#undef CHCRT_COUNT_NAMES

#define CHCRT_COUNT_CREATE(KIND, CREATE)                                                                              \
    void APIENTRY counted_##CREATE(GLsizei n, GLuint* names) {                                                         \
        gReal.CREATE(n, names);                                                                                        \
        add(KIND, nonZero(n, names));                                                                                  \
    }
CHCRT_COUNT_CREATE(Buffers, createBuffers)
CHCRT_COUNT_CREATE(Framebuffers, createFramebuffers)
CHCRT_COUNT_CREATE(Renderbuffers, createRenderbuffers)
CHCRT_COUNT_CREATE(VertexArrays, createVertexArrays)
CHCRT_COUNT_CREATE(Samplers, createSamplers)
#undef CHCRT_COUNT_CREATE

void APIENTRY counted_createTextures(GLenum target, GLsizei n, GLuint* names) {
    gReal.createTextures(target, n, names);
    add(Textures, nonZero(n, names));
}
void APIENTRY counted_createQueries(GLenum target, GLsizei n, GLuint* names) {
    gReal.createQueries(target, n, names);
    add(Queries, nonZero(n, names));
}
GLuint APIENTRY counted_createProgram() {
    const GLuint id = gReal.createProgram();
    if (id != 0) add(Programs, 1);
    return id;
}
GLuint APIENTRY counted_createShaderProgramv(GLenum type, GLsizei count, const GLchar* const* strings) {
    const GLuint id = gReal.createShaderProgramv(type, count, strings);
    if (id != 0) add(Programs, 1);
    return id;
}
void APIENTRY counted_deleteProgram(GLuint id) {
    if (id != 0) add(Programs, -1);
    gReal.deleteProgram(id);
}
GLuint APIENTRY counted_createShader(GLenum type) {
    const GLuint id = gReal.createShader(type);
    if (id != 0) add(Shaders, 1);
    return id;
}
void APIENTRY counted_deleteShader(GLuint id) {
    if (id != 0) add(Shaders, -1);
    gReal.deleteShader(id);
}
GLsync APIENTRY counted_fenceSync(GLenum condition, GLbitfield flags) {
    GLsync sync = gReal.fenceSync(condition, flags);
    if (sync != nullptr) add(Syncs, 1);
    return sync;
}
void APIENTRY counted_deleteSync(GLsync sync) {
    if (sync != nullptr) add(Syncs, -1);
    gReal.deleteSync(sync);
}

} // namespace

std::vector<std::pair<std::string, int64_t>> GlObjectCounts::named() const {
    return {{"buffers", buffers},   {"textures", textures}, {"framebuffers", framebuffers},
            {"renderbuffers", renderbuffers}, {"vertex_arrays", vertexArrays}, {"queries", queries},
            {"samplers", samplers}, {"programs", programs}, {"shaders", shaders}, {"syncs", syncs}};
}

GlObjectCounts liveGlObjects() {
    const auto get = [](Kind k) { return gLive[k].load(std::memory_order_relaxed); };
    GlObjectCounts c;
    c.buffers = get(Buffers);
    c.textures = get(Textures);
    c.framebuffers = get(Framebuffers);
    c.renderbuffers = get(Renderbuffers);
    c.vertexArrays = get(VertexArrays);
    c.queries = get(Queries);
    c.samplers = get(Samplers);
    c.programs = get(Programs);
    c.shaders = get(Shaders);
    c.syncs = get(Syncs);
    return c;
}

void detail::installGlObjectCounting() {
    // A slot left empty by the driver stays empty (loadGlFunctions reports missing core functions).
#define CHCRT_WRAP(SLOT, FIELD)                                                                                       \
    gReal.FIELD = SLOT;                                                                                                \
    if (gReal.FIELD != nullptr) SLOT = &counted_##FIELD;
    CHCRT_WRAP(glGenBuffers, genBuffers)
    CHCRT_WRAP(glCreateBuffers, createBuffers)
    CHCRT_WRAP(glDeleteBuffers, deleteBuffers)
    CHCRT_WRAP(glGenTextures, genTextures)
    CHCRT_WRAP(glCreateTextures, createTextures)
    CHCRT_WRAP(glDeleteTextures, deleteTextures)
    CHCRT_WRAP(glGenFramebuffers, genFramebuffers)
    CHCRT_WRAP(glCreateFramebuffers, createFramebuffers)
    CHCRT_WRAP(glDeleteFramebuffers, deleteFramebuffers)
    CHCRT_WRAP(glGenRenderbuffers, genRenderbuffers)
    CHCRT_WRAP(glCreateRenderbuffers, createRenderbuffers)
    CHCRT_WRAP(glDeleteRenderbuffers, deleteRenderbuffers)
    CHCRT_WRAP(glGenVertexArrays, genVertexArrays)
    CHCRT_WRAP(glCreateVertexArrays, createVertexArrays)
    CHCRT_WRAP(glDeleteVertexArrays, deleteVertexArrays)
    CHCRT_WRAP(glGenQueries, genQueries)
    CHCRT_WRAP(glCreateQueries, createQueries)
    CHCRT_WRAP(glDeleteQueries, deleteQueries)
    CHCRT_WRAP(glGenSamplers, genSamplers)
    CHCRT_WRAP(glCreateSamplers, createSamplers)
    CHCRT_WRAP(glDeleteSamplers, deleteSamplers)
    CHCRT_WRAP(glCreateProgram, createProgram)
    CHCRT_WRAP(glCreateShaderProgramv, createShaderProgramv)
    CHCRT_WRAP(glDeleteProgram, deleteProgram)
    CHCRT_WRAP(glCreateShader, createShader)
    CHCRT_WRAP(glDeleteShader, deleteShader)
    CHCRT_WRAP(glFenceSync, fenceSync)
    CHCRT_WRAP(glDeleteSync, deleteSync)
#undef CHCRT_WRAP
}

} // namespace chcrt
