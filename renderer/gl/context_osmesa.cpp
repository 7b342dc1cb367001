// OSMesa: Mesa's off-screen context, the second headless backend (and the one that common GL loaders cannot
// serve: libepoxy, GLEW and glbinding work with EGL and GLX contexts but fail with OSMesa). This is the only
// translation unit that includes <GL/osmesa.h>: it pulls in <GL/gl.h>, which cannot coexist with the generated
// loader header, so nothing here calls GL itself.
#include "renderer/core/error.h"
#include "renderer/gl/gl_internal.h"

#include <GL/osmesa.h>

#include <array>

namespace chcrt::detail {
namespace {

void* osMesaProcLoader(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

class OsMesaContext final : public HeadlessContext {
public:
    explicit OsMesaContext(OSMesaContext context) : context_(context) {}
    ~OsMesaContext() override {
        OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0); // release (gallium's OSMesa accepts NULL, NULL)
        OSMesaDestroyContext(context_);
    }
    OsMesaContext(const OsMesaContext&) = delete;
    OsMesaContext& operator=(const OsMesaContext&) = delete;

    void makeCurrent() {
        // OSMesaMakeCurrent refuses a NULL buffer. The renderer draws into FBOs only, so this tiny default
        // framebuffer is never read; it lives as long as the context.
        if (OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize) != GL_TRUE) {
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
    OSMesaContext context = OSMesaCreateContextAttribs(attribs, nullptr);
    if (context == nullptr) {
        throw GlError("OSMesa: OSMesaCreateContextAttribs could not create an OpenGL 4.5 core context "
                      "(is libosmesa6 from Mesa >= 20 installed? GALLIUM_DRIVER must be unset or llvmpipe)");
    }
    auto result = std::make_unique<OsMesaContext>(context);
    result->makeCurrent();
    return result;
}

} // namespace chcrt::detail
