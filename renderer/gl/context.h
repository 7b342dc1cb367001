#pragma once
// OpenGL 4.5 core contexts: headless EGL (default: EGL_EXT_platform_device, else the surfaceless Mesa
// platform), OSMesa, and (in the viewer) a GLFW window. After creation the context is current and the GL
// function table is loaded.
#include <memory>
#include <string>

namespace chcrt {

enum class GlBackend { Egl, OsMesa };

// "egl" | "osmesa"; throws InputError otherwise.
GlBackend parseGlBackend(const std::string& name);
const char* toString(GlBackend backend);

class GlContext {
public:
    virtual ~GlContext() = default;
    virtual std::string description() const = 0; // e.g. "EGL (device platform)"
};

// Creates a headless 4.5 core context, makes it current, loads GL functions, checks required features and,
// when `debugOutput` is true, installs the KHR_debug callback. `eglDevice` >= 0 (EGL only) uses that device of
// the EGL device list and nothing else (a farm task bound to one GPU, docs/farm.md); -1 tries the devices in
// order, then Mesa's surfaceless platform. Throws GlError with a clear message.
std::unique_ptr<GlContext> createHeadlessContext(GlBackend backend, bool debugOutput = false, int eglDevice = -1);

struct GlInfo {
    std::string vendor, renderer, version, glslVersion;
    int maxTextureBufferSize = 0; // texels
    int maxTextureSize = 0;
    int maxDrawBuffers = 0;
    int maxColorAttachments = 0;
    int maxFragmentUniformComponents = 0;
    int queryCounterBitsSamplesPassed = 0;
    bool khrDebug = false;
};
GlInfo queryGlInfo();

// The smallest GL_MAX_TEXTURE_BUFFER_SIZE the renderer accepts: scene data lives in texture buffers.
inline constexpr int kMinTextureBufferTexelsLog2 = 26;
inline constexpr int kMinTextureBufferTexels = 1 << kMinTextureBufferTexelsLog2; // 64M

// Throws GlError naming the first missing requirement: GL >= 4.5 core, texture buffers of at least
// kMinTextureBufferTexels texels, RGBA32F colour targets, 4+ draw buffers, occlusion + timer queries, KHR_debug
// (optional: warns only). Extensions are tested by name, never by function pointer.
void checkRequiredGlFeatures();

// True when the current context lists the extension (glGetStringi); never inferred from function pointers.
// (Added by the GL infrastructure work, beyond the original interface.)
bool hasGlExtension(const std::string& name);

// Routes KHR_debug messages (errors, warnings, performance) to stderr with source/type/severity.
// When `throwOnError` is set, GL errors reported through the callback are remembered and the next
// checkGlErrors() call throws them.
void enableGlDebugOutput(bool throwOnError = true);

// Throws GlError with `where` and the error name when glGetError() reports anything (or the debug callback
// recorded an error since the last call).
void checkGlErrors(const char* where);

} // namespace chcrt
