// OSMesa: Mesa's off-screen context, the second headless backend (and the one that common GL loaders cannot
// serve: libepoxy, GLEW and glbinding work with EGL and GLX contexts but fail with OSMesa). This is the only
// translation unit that includes <GL/osmesa.h>: it pulls in <GL/gl.h>, which cannot coexist with the generated
// loader header, so nothing here calls GL itself.
// libOSMesa is not linked: it is opened with dlopen the first time `--gl osmesa` asks for a context, so the binary
// runs where only libEGL is installed (the GPU bundle, docs/gpu.md) and OSMesa's absence is an error of that flag
// alone. The header is needed at build time only, for the types and constants.
#include "renderer/core/error.h"
#include "renderer/gl/gl_internal.h"

#include <GL/osmesa.h>

#include <dlfcn.h>

#include <array>
#include <cstdlib>
#include <mutex>
#include <string>

namespace chcrt::detail {
namespace {

// The OSMesa entry points chcrt uses, resolved from the dlopen'ed library. The library stays loaded for the life
// of the process (Mesa does not support being unloaded).
struct OsMesaApi {
    OSMesaContext (*createContextAttribs)(const int*, OSMesaContext) = nullptr;
    GLboolean (*makeCurrent)(OSMesaContext, void*, GLenum, GLsizei, GLsizei) = nullptr;
    void (*destroyContext)(OSMesaContext) = nullptr;
    OSMESAproc (*getProcAddress)(const char*) = nullptr;
};

// Library names tried in order; CHCRT_OSMESA_LIBRARY (a file name or path) replaces them.
constexpr const char* kOsMesaLibraries[] = {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"};

const OsMesaApi& osMesaApi() {
    static OsMesaApi api;
    static std::string error;
    static std::once_flag once;
    std::call_once(once, [] {
        void* library = nullptr;
        std::string tried;
        const char* override = std::getenv("CHCRT_OSMESA_LIBRARY");
        if (override != nullptr && *override != '\0') {
            library = ::dlopen(override, RTLD_NOW | RTLD_LOCAL);
            tried = override;
        } else {
            for (const char* name : kOsMesaLibraries) {
                library = ::dlopen(name, RTLD_NOW | RTLD_LOCAL);
                tried += std::string(tried.empty() ? "" : ", ") + name;
                if (library != nullptr) break;
            }
        }
        if (library == nullptr) {
            const char* reason = ::dlerror();
            error = "--gl osmesa: cannot load OSMesa (tried " + tried + ": " + (reason ? reason : "not found") +
                    "); install Mesa's OSMesa (Debian: libosmesa6) or use --gl egl";
            return;
        }
        const auto resolve = [&](const char* name) -> void* {
            void* symbol = ::dlsym(library, name);
            if (symbol == nullptr && error.empty()) {
                error = std::string("--gl osmesa: the OSMesa library has no ") + name + " (Mesa >= 20 is required)";
            }
            return symbol;
        };
        api.createContextAttribs =
            reinterpret_cast<decltype(api.createContextAttribs)>(resolve("OSMesaCreateContextAttribs"));
        api.makeCurrent = reinterpret_cast<decltype(api.makeCurrent)>(resolve("OSMesaMakeCurrent"));
        api.destroyContext = reinterpret_cast<decltype(api.destroyContext)>(resolve("OSMesaDestroyContext"));
        api.getProcAddress = reinterpret_cast<decltype(api.getProcAddress)>(resolve("OSMesaGetProcAddress"));
    });
    if (!error.empty()) throw GlError(error);
    return api;
}

void* osMesaProcLoader(const char* name) { return reinterpret_cast<void*>(osMesaApi().getProcAddress(name)); }

class OsMesaContext final : public HeadlessContext {
public:
    explicit OsMesaContext(OSMesaContext context) : context_(context) {}
    ~OsMesaContext() override {
        const OsMesaApi& api = osMesaApi();
        api.makeCurrent(nullptr, nullptr, 0, 0, 0); // release (gallium's OSMesa accepts NULL, NULL)
        api.destroyContext(context_);
    }
    OsMesaContext(const OsMesaContext&) = delete;
    OsMesaContext& operator=(const OsMesaContext&) = delete;

    void makeCurrent() {
        // OSMesaMakeCurrent refuses a NULL buffer. The renderer draws into FBOs only, so this tiny default
        // framebuffer is never read; it lives as long as the context.
        if (osMesaApi().makeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize) != GL_TRUE) {
            throw GlError("OSMesa: OSMesaMakeCurrent failed");
        }
    }
    std::string description() const override { return "OSMesa (4.5 core)"; }
    ProcLoader procLoader() const override { return &osMesaProcLoader; }

private:
    static constexpr int kSize = 4;
    OSMesaContext context_;
    std::array<unsigned char, kSize * kSize * 4> buffer_{};
};

} // namespace

std::unique_ptr<HeadlessContext> createOsMesaContext(bool /*debugContext*/) {
    const OsMesaApi& api = osMesaApi(); // throws when the library cannot be loaded
    // OSMesa has no debug-context attribute; KHR_debug output is still enabled with glEnable(GL_DEBUG_OUTPUT)
    // by enableGlDebugOutput(). The default framebuffer needs no depth or stencil: passes use FBOs.
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA,
                           OSMESA_DEPTH_BITS, 0,
                           OSMESA_STENCIL_BITS, 0,
                           OSMESA_ACCUM_BITS, 0,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 4,
                           OSMESA_CONTEXT_MINOR_VERSION, 5,
                           0};
    OSMesaContext context = api.createContextAttribs(attribs, nullptr);
    if (context == nullptr) {
        throw GlError("OSMesa: OSMesaCreateContextAttribs could not create an OpenGL 4.5 core context "
                      "(is libosmesa6 from Mesa >= 20 installed? GALLIUM_DRIVER must be unset or llvmpipe)");
    }
    auto result = std::make_unique<OsMesaContext>(context);
    result->makeCurrent();
    return result;
}

} // namespace chcrt::detail
