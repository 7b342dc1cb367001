#pragma once
// OpenGL 4.5 core contexts: headless EGL (default: EGL_EXT_platform_device, else the surfaceless Mesa
// platform), OSMesa, and (in the viewer) a GLFW window. After creation the context is current and the GL
// function table is loaded.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

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

// --gl-device auto: prefer a hardware EGL device, fall back to software ones (createHeadlessContext).
inline constexpr int kAutoGlDevice = -1;

// Creates a headless 4.5 core context, makes it current, loads GL functions, checks required features and,
// when `debugOutput` is true, installs the KHR_debug callback. `eglDevice` >= 0 (EGL only) uses that device of
// the EGL device list and nothing else (a farm task bound to one GPU, docs/farm.md); kAutoGlDevice tries the
// hardware devices in list order, then the software ones (EGL_MESA_device_software), then Mesa's surfaceless
// platform. Whether the context renders in software is for the caller to say (currentRendererTraits()).
// Throws GlError with a clear message.
std::unique_ptr<GlContext> createHeadlessContext(GlBackend backend, bool debugOutput = false,
                                                 int eglDevice = kAutoGlDevice);

// An EGL device of the device list (EGL_EXT_device_enumeration), as far as the driver describes it.
struct EglDeviceInfo {
    int index = 0;
    bool software = false;  // EGL_MESA_device_software (llvmpipe); NVIDIA's and Mesa's hardware devices lack it
    std::string renderer;   // EGL_RENDERER_EXT (EGL_EXT_device_query_name), "" where not offered
    std::string vendor;     // EGL_VENDOR of the device (EGL_EXT_device_query_name)
    std::string drmDevice;  // EGL_DRM_DEVICE_FILE_EXT (EGL_EXT_device_drm), e.g. /dev/dri/card0
    std::string extensions; // the device's extension string
};
// The EGL devices in list order (the indices --gl-device takes); empty when EGL has no device enumeration.
// Throws GlError only when libEGL itself is unusable.
std::vector<EglDeviceInfo> listEglDevices();

// What the shaders and the reports adapt to in a GL renderer, from its GL_RENDERER string (rendererTraits): the one
// place where chcrt looks at a vendor's name, for facts no capability query reveals.
struct RendererTraits {
    // A CPU rasteriser (llvmpipe, softpipe, swrast, SwiftShader): its timings are not GPU timings.
    bool software = false;
    // Loops end silently after 65,535 iterations per invocation (llvmpipe, Mesa's gallivm): tracers count their
    // iterations and flag rays that reach CHCRT_TRACE_ITERATION_CAP (shaders/shared/render_layout.h).
    bool loopCap = false;
};
RendererTraits rendererTraits(const std::string& glRenderer);
// Of the current context (GL_RENDERER queried on each call).
RendererTraits currentRendererTraits();

// GPU memory as the driver reports it: GL_NVX_gpu_memory_info (NVIDIA: total and currently available video
// memory) or GL_ATI_meminfo (AMD: free texture memory, no total). Not reported by llvmpipe.
struct GpuMemoryInfo {
    bool reported = false;
    uint64_t totalBytes = 0;     // 0 where the extension gives no total
    uint64_t availableBytes = 0;
    std::string source;          // the extension that reported it
};
GpuMemoryInfo queryGpuMemory();

struct GlInfo {
    std::string vendor, renderer, version, glslVersion;
    bool softwareRenderer = false; // rendererTraits(renderer).software
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
