// Headless EGL: OpenGL 4.5 core contexts without a display server, made current with no surface (the renderer
// draws into FBOs only). The device platform (EGL_EXT_platform_device) comes first because it is how NVIDIA's
// driver runs headless; Mesa's surfaceless platform is the fallback (both need no display server; plain
// eglGetDisplay fails without one unless EGL_PLATFORM=surfaceless is set).
// CHCRT_EGL_PLATFORM=device|surfaceless restricts the search to one platform (tests use it to cover both).
// Devices: --gl-device N takes device N of the EGL device list and nothing else; auto (the default) takes the first
// hardware device that makes a context, then software devices (EGL_MESA_device_software), then surfaceless.
#define EGL_NO_X11 // keep X11's macros (None, Bool, ...) out of this translation unit
#include "renderer/core/error.h"
#include "renderer/gl/gl_internal.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace chcrt::detail {
namespace {

bool hasEglExtension(const char* extensions, std::string_view name) {
    if (extensions == nullptr) {
        return false;
    }
    std::string_view list(extensions);
    size_t pos = 0;
    while (pos < list.size()) {
        size_t end = list.find(' ', pos);
        if (end == std::string_view::npos) {
            end = list.size();
        }
        if (list.substr(pos, end - pos) == name) {
            return true;
        }
        pos = end + 1;
    }
    return false;
}

std::string eglErrorName(EGLint error) {
    switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: {
        std::ostringstream s;
        s << "EGL error 0x" << std::hex << error;
        return s.str();
    }
    }
}

void* eglProcLoader(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

class EglContext final : public HeadlessContext {
public:
    EglContext(EGLDisplay display, EGLContext context, std::string description)
        : display_(display), context_(context), description_(std::move(description)) {}
    ~EglContext() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        eglTerminate(display_);
        eglReleaseThread();
    }
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;
    std::string description() const override { return description_; }
    ProcLoader procLoader() const override { return &eglProcLoader; }

private:
    EGLDisplay display_;
    EGLContext context_;
    std::string description_;
};

// Initializes `display` and makes a 4.5 core context current on it with no surface. On failure, terminates the
// display, appends the reason to `why` and returns nullptr.
std::unique_ptr<HeadlessContext> tryDisplay(EGLDisplay display, bool debugContext, const std::string& label,
                                            std::string& why) {
    auto fail = [&](const std::string& reason) -> std::unique_ptr<HeadlessContext> {
        why += (why.empty() ? "" : "; ") + label + ": " + reason;
        if (display != EGL_NO_DISPLAY) {
            eglTerminate(display);
        }
        return nullptr;
    };
    if (display == EGL_NO_DISPLAY) {
        return fail("no display (" + eglErrorName(eglGetError()) + ")");
    }
    EGLint major = 0, minor = 0;
    if (eglInitialize(display, &major, &minor) != EGL_TRUE) {
        return fail("eglInitialize failed (" + eglErrorName(eglGetError()) + ")");
    }
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasEglExtension(extensions, "EGL_KHR_surfaceless_context")) {
        return fail("no EGL_KHR_surfaceless_context");
    }
    const bool egl15 = major > 1 || (major == 1 && minor >= 5);
    if (!egl15 && !hasEglExtension(extensions, "EGL_KHR_create_context")) {
        return fail("EGL " + std::to_string(major) + "." + std::to_string(minor) +
                    " without EGL_KHR_create_context");
    }
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
        return fail("eglBindAPI(EGL_OPENGL_API) failed (" + eglErrorName(eglGetError()) + ")");
    }
    // No surface will be created, so any surface type will do (the EGL default would demand a window).
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configCount = 0;
    if (eglChooseConfig(display, configAttribs, &config, 1, &configCount) != EGL_TRUE || configCount == 0) {
        return fail("no config with EGL_OPENGL_BIT");
    }
    std::vector<EGLint> contextAttribs = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                          EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
    if (debugContext) {
        // EGL 1.5 has its own attribute; 1.4 + EGL_KHR_create_context uses the flags word.
        contextAttribs.insert(contextAttribs.end(), {egl15 ? EGL_CONTEXT_OPENGL_DEBUG : EGL_CONTEXT_FLAGS_KHR,
                                                     egl15 ? EGL_TRUE : EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR});
    }
    contextAttribs.push_back(EGL_NONE);
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs.data());
    if (context == EGL_NO_CONTEXT) {
        return fail("eglCreateContext(4.5 core) failed (" + eglErrorName(eglGetError()) + ")");
    }
    if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
        const EGLint error = eglGetError();
        eglDestroyContext(display, context);
        return fail("eglMakeCurrent without surface failed (" + eglErrorName(error) + ")");
    }
    const char* vendor = eglQueryString(display, EGL_VENDOR);
    return std::make_unique<EglContext>(display, context,
                                        "EGL " + std::to_string(major) + "." + std::to_string(minor) + " (" +
                                            label + ", " + (vendor != nullptr ? vendor : "unknown vendor") + ")");
}

} // namespace

namespace {

// Device-query enums that older eglext.h files lack.
#ifndef EGL_RENDERER_EXT
#define EGL_RENDERER_EXT 0x335F // EGL_EXT_device_query_name
#endif
#ifndef EGL_DRM_DEVICE_FILE_EXT
#define EGL_DRM_DEVICE_FILE_EXT 0x3233 // EGL_EXT_device_drm
#endif

// Client extensions (EGL_NO_DISPLAY) say which platforms exist; entry points of extensions are fetched with
// eglGetProcAddress, and only after their extension string was seen.
const char* clientExtensionsOrThrow() {
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (clientExtensions == nullptr || !hasEglExtension(clientExtensions, "EGL_EXT_platform_base")) {
        // glvnd's libEGL without a vendor (driver) says so too: it reads vendor files only from
        // /usr/share/glvnd/egl_vendor.d and /etc/glvnd/egl_vendor.d unless __EGL_VENDOR_LIBRARY_DIRS names others.
        throw GlError("EGL: the EGL library lacks EGL_EXT_platform_base, so no headless display can be opened "
                      "(no EGL driver found: is libegl1 from glvnd or Mesa installed, and is the driver's vendor file "
                      "in /usr/share/glvnd/egl_vendor.d or named by __EGL_VENDOR_LIBRARY_DIRS?)");
    }
    return clientExtensions;
}

bool hasDeviceEnumeration(const char* clientExtensions) {
    return hasEglExtension(clientExtensions, "EGL_EXT_device_enumeration") ||
           hasEglExtension(clientExtensions, "EGL_EXT_device_base");
}

// The EGL devices (empty without device enumeration or when the driver lists none).
std::vector<EGLDeviceEXT> queryDevices(const char* clientExtensions) {
    if (!hasDeviceEnumeration(clientExtensions)) return {};
    auto query = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLint count = 0;
    if (query == nullptr || query(0, nullptr, &count) != EGL_TRUE || count <= 0) return {};
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
    if (query(count, devices.data(), &count) != EGL_TRUE) return {};
    devices.resize(static_cast<size_t>(std::max(count, 0)));
    return devices;
}

EglDeviceInfo describeDevice(EGLDeviceEXT device, int index) {
    EglDeviceInfo info;
    info.index = index;
    auto queryString =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (queryString == nullptr) return info;
    const auto text = [&](EGLint name) {
        const char* value = queryString(device, name);
        return std::string(value != nullptr ? value : "");
    };
    info.extensions = text(EGL_EXTENSIONS);
    const char* extensions = info.extensions.c_str();
    info.software = hasEglExtension(extensions, "EGL_MESA_device_software");
    if (hasEglExtension(extensions, "EGL_EXT_device_query_name")) {
        info.renderer = text(EGL_RENDERER_EXT);
        info.vendor = text(EGL_VENDOR);
    }
    if (hasEglExtension(extensions, "EGL_EXT_device_drm")) info.drmDevice = text(EGL_DRM_DEVICE_FILE_EXT);
    eglGetError(); // a device refusing a query it lists leaves nothing behind
    return info;
}

} // namespace

std::unique_ptr<HeadlessContext> createEglContext(bool debugContext, int device) {
    const char* forced = std::getenv("CHCRT_EGL_PLATFORM");
    const std::string only = forced != nullptr ? forced : "";
    if (!only.empty() && only != "device" && only != "surfaceless") {
        throw GlError("EGL: CHCRT_EGL_PLATFORM must be 'device' or 'surfaceless', not '" + only + "'");
    }
    const char* clientExtensions = clientExtensionsOrThrow();
    auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    std::string why;

    // Step 1: the device platform: the device asked for, or (auto) the hardware devices, then the software ones.
    if (only != "surfaceless") {
        if (hasEglExtension(clientExtensions, "EGL_EXT_platform_device") && hasDeviceEnumeration(clientExtensions)) {
            const std::vector<EGLDeviceEXT> devices = queryDevices(clientExtensions);
            const int deviceCount = int(devices.size());
            if (deviceCount == 0) why += "device platform: no devices";
            const auto label = [&](int i, bool software) {
                return "device platform, device " + std::to_string(i) + " of " + std::to_string(deviceCount) +
                       (software ? ", software" : "");
            };
            if (device >= 0) { // that device or nothing: a task bound to one GPU must not run on another
                if (device >= deviceCount) {
                    throw GlError("EGL: --gl-device " + std::to_string(device) + " does not exist (" +
                                  std::to_string(deviceCount) + " EGL device(s); chcrt info --devices lists them)");
                }
                const bool software = describeDevice(devices[size_t(device)], device).software;
                EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[size_t(device)], nullptr);
                if (auto context = tryDisplay(display, debugContext, label(device, software), why)) return context;
                throw GlError("EGL: --gl-device " + std::to_string(device) + " cannot create an OpenGL 4.5 core context (" +
                              why + ")");
            }
            for (bool software : {false, true}) {
                for (int i = 0; i < deviceCount; ++i) {
                    if (describeDevice(devices[size_t(i)], i).software != software) continue;
                    EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[size_t(i)], nullptr);
                    if (auto context = tryDisplay(display, debugContext, label(i, software), why)) return context;
                }
            }
        } else {
            why += "device platform: not supported";
        }
    }
    if (device >= 0) throw GlError("EGL: --gl-device needs the EGL device platform (" + why + ")");

    // Step 2: Mesa's surfaceless platform.
    if (only != "device") {
        if (hasEglExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
            EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
            if (auto context = tryDisplay(display, debugContext, "surfaceless platform", why)) {
                return context;
            }
        } else {
            why += std::string(why.empty() ? "" : "; ") + "surfaceless platform: not supported";
        }
    }
    throw GlError("EGL: no device or surfaceless platform could create an OpenGL 4.5 core context (" + why +
                  "); is libgl1-mesa-dri installed, or try the OSMesa backend");
}

} // namespace chcrt::detail

namespace chcrt {

std::vector<EglDeviceInfo> listEglDevices() {
    const char* clientExtensions = detail::clientExtensionsOrThrow();
    const std::vector<EGLDeviceEXT> devices = detail::queryDevices(clientExtensions);
    std::vector<EglDeviceInfo> infos;
    for (size_t i = 0; i < devices.size(); ++i) infos.push_back(detail::describeDevice(devices[i], int(i)));
    return infos;
}

} // namespace chcrt
