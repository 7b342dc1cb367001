// Backend-independent context code: backend selection, the feature check every renderer path relies on, and
// error reporting (glGetError + KHR_debug).
#include "renderer/gl/context.h"

#include "renderer/core/error.h"
#include "renderer/gl/gl.h"
#include "renderer/gl/gl_internal.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <mutex>
#include <string>

namespace chcrt {
namespace {

// Errors seen by the KHR_debug callback since the last checkGlErrors(); the callback may run on a driver
// thread when output is asynchronous, hence the mutex.
struct DebugState {
    std::mutex mutex;
    bool recordErrors = false;
    int errorCount = 0;
    std::string firstError;
};
DebugState& debugState() {
    static DebugState state;
    return state;
}

const char* glErrorName(GLenum error) {
    switch (error) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    default: return "unknown GL error";
    }
}

const char* debugSourceName(GLenum source) {
    switch (source) {
    case GL_DEBUG_SOURCE_API: return "api";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM: return "window-system";
    case GL_DEBUG_SOURCE_SHADER_COMPILER: return "shader-compiler";
    case GL_DEBUG_SOURCE_THIRD_PARTY: return "third-party";
    case GL_DEBUG_SOURCE_APPLICATION: return "application";
    default: return "other";
    }
}

const char* debugTypeName(GLenum type) {
    switch (type) {
    case GL_DEBUG_TYPE_ERROR: return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined-behaviour";
    case GL_DEBUG_TYPE_PORTABILITY: return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE: return "performance";
    case GL_DEBUG_TYPE_MARKER: return "marker";
    default: return "other";
    }
}

const char* debugSeverityName(GLenum severity) {
    switch (severity) {
    case GL_DEBUG_SEVERITY_HIGH: return "high";
    case GL_DEBUG_SEVERITY_MEDIUM: return "medium";
    case GL_DEBUG_SEVERITY_LOW: return "low";
    default: return "notification";
    }
}

void APIENTRY onDebugMessage(GLenum source, GLenum type, GLuint /*id*/, GLenum severity, GLsizei /*length*/,
                             const GLchar* message, const void* /*userParam*/) {
    // Compiler messages are skipped: ShaderProgram throws them with file names mapped (their "0:12(5)" source
    // numbers mean nothing here), and a failed compile is not a GL API error.
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION || source == GL_DEBUG_SOURCE_SHADER_COMPILER) {
        return;
    }
    std::fprintf(stderr, "GL %s [%s] %s: %s\n", debugTypeName(type), debugSeverityName(severity),
                 debugSourceName(source), message);
    if (type == GL_DEBUG_TYPE_ERROR) {
        DebugState& state = debugState();
        std::lock_guard<std::mutex> lock(state.mutex);
        if (state.recordErrors && state.errorCount++ == 0) {
            state.firstError = message;
        }
    }
}

int getInteger(GLenum name) {
    GLint value = 0;
    glGetIntegerv(name, &value);
    return value;
}

std::string getString(GLenum name) {
    const GLubyte* text = glGetString(name);
    return text != nullptr ? reinterpret_cast<const char*>(text) : "";
}

} // namespace

GlBackend parseGlBackend(const std::string& name) {
    if (name == "egl") {
        return GlBackend::Egl;
    }
    if (name == "osmesa") {
        return GlBackend::OsMesa;
    }
    throw InputError("unknown GL backend '" + name + "' (expected egl or osmesa)");
}

const char* toString(GlBackend backend) { return backend == GlBackend::Egl ? "egl" : "osmesa"; }

std::unique_ptr<GlContext> createHeadlessContext(GlBackend backend, bool debugOutput, int eglDevice) {
    if (backend != GlBackend::Egl && eglDevice != kAutoGlDevice) {
        throw InputError("--gl-device needs --gl egl (OSMesa has no devices)");
    }
    std::unique_ptr<detail::HeadlessContext> context =
        backend == GlBackend::Egl ? detail::createEglContext(debugOutput, eglDevice) : detail::createOsMesaContext(debugOutput);
    {
        DebugState& state = debugState();
        std::lock_guard<std::mutex> lock(state.mutex);
        state.recordErrors = false;
        state.errorCount = 0;
        state.firstError.clear();
    }
    // On a throw below, `context` is destroyed, so a failed check leaves no context current.
    loadGlFunctions(context->procLoader());
    checkRequiredGlFeatures();
    if (debugOutput) {
        enableGlDebugOutput(true);
    }
    return context;
}

bool hasGlExtension(const std::string& name) {
    const int count = getInteger(GL_NUM_EXTENSIONS);
    for (int i = 0; i < count; ++i) {
        const GLubyte* extension = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
        if (extension != nullptr && name == reinterpret_cast<const char*>(extension)) {
            return true;
        }
    }
    return false;
}

RendererTraits rendererTraits(const std::string& glRenderer) {
    std::string name = glRenderer;
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    const auto has = [&name](const char* part) { return name.find(part) != std::string::npos; };
    RendererTraits traits;
    traits.software = has("llvmpipe") || has("softpipe") || has("swrast") || has("software rasterizer") ||
                      has("swiftshader");
    // Mesa's gallivm ends loops after LP_MAX_TGSI_LOOP_ITERATIONS (65,535); of the GL drivers it compiles shaders
    // for, llvmpipe is the one that runs fragment and compute shaders.
    traits.loopCap = has("llvmpipe");
    return traits;
}

RendererTraits currentRendererTraits() { return rendererTraits(getString(GL_RENDERER)); }

GpuMemoryInfo queryGpuMemory() {
    // Enums of the two extensions (not in the core 4.5 headers the loader is generated from); values in KiB.
    constexpr GLenum kNvxTotalAvailableMemory = 0x9048;   // GL_GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX
    constexpr GLenum kNvxCurrentAvailableVidmem = 0x9049; // GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX
    constexpr GLenum kAtiTextureFreeMemory = 0x87FC;      // GL_TEXTURE_FREE_MEMORY_ATI: 4 values, [0] = total free
    GpuMemoryInfo info;
    if (hasGlExtension("GL_NVX_gpu_memory_info")) {
        GLint total = 0, available = 0;
        glGetIntegerv(kNvxTotalAvailableMemory, &total);
        glGetIntegerv(kNvxCurrentAvailableVidmem, &available);
        info = {true, uint64_t(std::max(total, 0)) << 10, uint64_t(std::max(available, 0)) << 10, "GL_NVX_gpu_memory_info"};
    } else if (hasGlExtension("GL_ATI_meminfo")) {
        GLint free[4] = {0, 0, 0, 0};
        glGetIntegerv(kAtiTextureFreeMemory, free);
        info = {true, 0, uint64_t(std::max(free[0], 0)) << 10, "GL_ATI_meminfo"};
    }
    if (info.reported && info.availableBytes == 0) info = {}; // listed but answering nothing: not reported
    return info;
}

GlInfo queryGlInfo() {
    GlInfo info;
    info.vendor = getString(GL_VENDOR);
    info.renderer = getString(GL_RENDERER);
    info.softwareRenderer = rendererTraits(info.renderer).software;
    info.version = getString(GL_VERSION);
    info.glslVersion = getString(GL_SHADING_LANGUAGE_VERSION);
    info.maxTextureBufferSize = getInteger(GL_MAX_TEXTURE_BUFFER_SIZE);
    info.maxTextureSize = getInteger(GL_MAX_TEXTURE_SIZE);
    info.maxDrawBuffers = getInteger(GL_MAX_DRAW_BUFFERS);
    info.maxColorAttachments = getInteger(GL_MAX_COLOR_ATTACHMENTS);
    info.maxFragmentUniformComponents = getInteger(GL_MAX_FRAGMENT_UNIFORM_COMPONENTS);
    GLint bits = 0;
    glGetQueryiv(GL_SAMPLES_PASSED, GL_QUERY_COUNTER_BITS, &bits);
    info.queryCounterBitsSamplesPassed = bits;
    // KHR_debug is core since 4.3, but a driver may still list only the extension; either counts.
    const int version = getInteger(GL_MAJOR_VERSION) * 10 + getInteger(GL_MINOR_VERSION);
    info.khrDebug = version >= 43 || hasGlExtension("GL_KHR_debug");
    return info;
}

void checkRequiredGlFeatures() {
    // Step 1: version and profile. GL_MAJOR/MINOR_VERSION are integers, unlike the vendor-formatted string.
    const int major = getInteger(GL_MAJOR_VERSION);
    const int minor = getInteger(GL_MINOR_VERSION);
    if (major * 10 + minor < 45) {
        throw GlError("OpenGL 4.5 core is required, the context has " + std::to_string(major) + "." +
                      std::to_string(minor) + " (" + getString(GL_VERSION) + ")");
    }
    if ((getInteger(GL_CONTEXT_PROFILE_MASK) & GL_CONTEXT_CORE_PROFILE_BIT) == 0) {
        throw GlError("an OpenGL core profile context is required (" + getString(GL_VERSION) + ")");
    }
    // Step 2: limits the renderer's data layout depends on: scene data lives in texture buffers (~10x faster
    // than SSBOs on llvmpipe), the G-buffer writes 4 targets, accumulation needs RGBA32F targets.
    const int maxTextureBuffer = getInteger(GL_MAX_TEXTURE_BUFFER_SIZE);
    if (maxTextureBuffer < kMinTextureBufferTexels) {
        throw GlError("GL_MAX_TEXTURE_BUFFER_SIZE is " + std::to_string(maxTextureBuffer) + " texels; at least " +
                      std::to_string(kMinTextureBufferTexels >> 20) + "M (2^" +
                      std::to_string(kMinTextureBufferTexelsLog2) + ") are required");
    }
    const int maxDrawBuffers = getInteger(GL_MAX_DRAW_BUFFERS);
    if (maxDrawBuffers < 4 || getInteger(GL_MAX_COLOR_ATTACHMENTS) < 4) {
        throw GlError("at least 4 draw buffers are required, GL_MAX_DRAW_BUFFERS is " +
                      std::to_string(maxDrawBuffers));
    }
    GLint renderable = GL_NONE;
    glGetInternalformativ(GL_TEXTURE_2D, GL_RGBA32F, GL_FRAMEBUFFER_RENDERABLE, 1, &renderable);
    if (renderable != GL_FULL_SUPPORT) {
        throw GlError("RGBA32F textures must be fully colour-renderable (GL_FRAMEBUFFER_RENDERABLE)");
    }
    // Step 3: occlusion queries drive the CHC+RT culling; timer queries are used by --stats.
    GLint samplesBits = 0;
    glGetQueryiv(GL_SAMPLES_PASSED, GL_QUERY_COUNTER_BITS, &samplesBits);
    if (samplesBits <= 0) {
        throw GlError("occlusion queries are required but GL_QUERY_COUNTER_BITS of GL_SAMPLES_PASSED is 0");
    }
    GLint timerBits = 0;
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &timerBits);
    if (timerBits <= 0) {
        throw GlError("timer queries are required but GL_QUERY_COUNTER_BITS of GL_TIME_ELAPSED is 0");
    }
    if (!hasGlExtension("GL_KHR_debug") && major * 10 + minor < 43) {
        std::fprintf(stderr, "warning: KHR_debug is not available; GL errors are reported by glGetError only\n");
    }
    checkGlErrors("checkRequiredGlFeatures");
}

void enableGlDebugOutput(bool throwOnError) {
    {
        DebugState& state = debugState();
        std::lock_guard<std::mutex> lock(state.mutex);
        state.recordErrors = throwOnError;
    }
    glEnable(GL_DEBUG_OUTPUT);
    // Synchronous: the message arrives inside the offending call, so checkGlErrors() right after it sees it.
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(&onDebugMessage, nullptr);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
}

void checkGlErrors(const char* where) {
    std::string errors;
    // glGetError returns one flag per call; a bounded loop drains them (and cannot spin on a lost context).
    for (int i = 0; i < 16; ++i) {
        const GLenum error = glGetError();
        if (error == GL_NO_ERROR) {
            break;
        }
        errors += std::string(errors.empty() ? "" : ", ") + glErrorName(error);
    }
    std::string debugMessage;
    int debugErrors = 0;
    {
        DebugState& state = debugState();
        std::lock_guard<std::mutex> lock(state.mutex);
        debugErrors = state.errorCount;
        debugMessage = std::move(state.firstError);
        state.errorCount = 0;
        state.firstError.clear();
    }
    if (errors.empty() && debugErrors == 0) {
        return;
    }
    std::string message = std::string("GL error at ") + where + ": " + (errors.empty() ? "(debug output)" : errors);
    if (debugErrors > 0) {
        message += "; debug output: " + debugMessage;
        if (debugErrors > 1) {
            message += " (+" + std::to_string(debugErrors - 1) + " more)";
        }
    }
    throw GlError(message);
}

} // namespace chcrt
