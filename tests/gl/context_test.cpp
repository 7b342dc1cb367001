// Headless contexts: creation and destruction on both backends and both EGL platforms, the feature check,
// and error reporting through glGetError and KHR_debug. A platform or backend that the machine lacks (Mesa's
// surfaceless platform and OSMesa next to NVIDIA's driver, the device platform in an old libEGL) is skipped with
// the reason, judged by what EGL and the loader offer, never by a vendor's name.
#include "renderer/core/error.h"
#include "renderer/gl/gl_objects.h"
#include "tests/gl/gl_test_fixture.h"

#include <EGL/egl.h>
#include <dlfcn.h>

#include <chrono>
#include <cstdio>
#include <sstream>

namespace chcrt {
namespace {

using test::GlTest;

// Whether libEGL lists a client extension (EGL_NO_DISPLAY): which platforms exist at all.
bool hasEglClientExtension(const std::string& name) {
    const char* list = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    std::istringstream words(list != nullptr ? list : "");
    std::string word;
    while (words >> word) {
        if (word == name) return true;
    }
    return false;
}

// Whether Mesa's OSMesa library can be loaded on this machine (the OSMesa backend's runtime).
bool osMesaPresent() {
    void* library = dlopen("libOSMesa.so.8", RTLD_LAZY | RTLD_LOCAL);
    if (library == nullptr) return false;
    dlclose(library);
    return true;
}

#define SKIP_WITHOUT_OSMESA()                                                                                     \
    if (!osMesaPresent()) GTEST_SKIP() << "OSMesa (libOSMesa.so.8) is not installed: the OSMesa backend cannot run here"

// Proves the context and the loaded table work: clears an RGBA32F target and reads the value back.
void expectContextRenders(float value) {
    GlTexture texture = createTexture2D(4, 4, GL_RGBA32F);
    const GLuint colour = texture.id();
    GlFramebuffer framebuffer = createFramebuffer(&colour, 1);
    const float clear[4] = {value, 2.0f * value, -value, 1.0f};
    glClearNamedFramebufferfv(framebuffer.id(), GL_COLOR, 0, clear);
    for (const glm::vec4& texel : test::readTextureRgba32f(texture.id(), 4, 4)) {
        ASSERT_EQ(texel, glm::vec4(value, 2.0f * value, -value, 1.0f));
    }
    checkGlErrors("expectContextRenders");
}

// Creates, checks and destroys one context; returns the creation time in ms (reported, never asserted).
double createCheckDestroy(GlBackend backend, float clearValue, const char* expectedDescription) {
    const auto start = std::chrono::steady_clock::now();
    std::unique_ptr<GlContext> context = createHeadlessContext(backend);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    EXPECT_NE(context->description().find(expectedDescription), std::string::npos) << context->description();
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    EXPECT_GE(major * 10 + minor, 45);
    expectContextRenders(clearValue);
    std::printf("[ context  ] %s created in %.1f ms\n", context->description().c_str(), ms);
    return ms;
}

TEST(GlContext, EglCreateDestroyTwiceInARow) {
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", std::nullopt);
    createCheckDestroy(GlBackend::Egl, 0.25f, "EGL");
    // The second context must get a freshly loaded table and a working default (device) display again.
    createCheckDestroy(GlBackend::Egl, 0.75f, "EGL");
}

TEST(GlContext, EglDevicePlatform) {
    if (!hasEglClientExtension("EGL_EXT_platform_device")) {
        GTEST_SKIP() << "libEGL offers no EGL_EXT_platform_device: no device platform here";
    }
    if (listEglDevices().empty()) GTEST_SKIP() << "EGL lists no device";
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", "device");
    createCheckDestroy(GlBackend::Egl, 0.5f, "device platform");
}

TEST(GlContext, EglSurfacelessPlatform) {
    if (!hasEglClientExtension("EGL_MESA_platform_surfaceless")) {
        GTEST_SKIP() << "libEGL offers no EGL_MESA_platform_surfaceless (Mesa's EGL is not installed)";
    }
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", "surfaceless");
    createCheckDestroy(GlBackend::Egl, 0.5f, "surfaceless platform");
}

// Devices as listed: consecutive indices; a device that says it is software (EGL_MESA_device_software) makes a
// software renderer, one that does not makes a hardware renderer; an index past the list is refused by name.
TEST(GlContext, EglDevicesAreListedAndDescribeTheirRenderer) {
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", std::nullopt);
    const std::vector<EglDeviceInfo> devices = listEglDevices();
    if (devices.empty()) GTEST_SKIP() << "EGL lists no device (no EGL_EXT_device_enumeration)";
    for (size_t i = 0; i < devices.size(); ++i) {
        const EglDeviceInfo& d = devices[i];
        EXPECT_EQ(d.index, int(i));
        std::unique_ptr<GlContext> context;
        try {
            context = createHeadlessContext(GlBackend::Egl, false, d.index);
        } catch (const GlError& e) {
            std::printf("[ devices  ] device %d makes no 4.5 context: %s\n", d.index, e.what());
            continue; // listed devices need not all support OpenGL 4.5 (a display-only GPU)
        }
        const GlInfo info = queryGlInfo();
        std::printf("[ devices  ] device %d: %s%s\n", d.index, info.renderer.c_str(), d.software ? " (software)" : "");
        EXPECT_NE(context->description().find("device " + std::to_string(d.index)), std::string::npos)
            << context->description();
        EXPECT_EQ(info.softwareRenderer, d.software) << info.renderer;
    }
    try {
        createHeadlessContext(GlBackend::Egl, false, int(devices.size()));
        FAIL() << "no GlError for a device past the list";
    } catch (const GlError& e) {
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("info --devices"), std::string::npos) << e.what();
    }
    EXPECT_THROW(createHeadlessContext(GlBackend::OsMesa, false, 0), InputError);
}

// auto (the default) prefers hardware: whenever the list has a hardware device that makes a context, auto's
// context is not a software renderer.
TEST(GlContext, AutoDevicePrefersHardware) {
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", std::nullopt);
    bool hardwareWorks = false;
    for (const EglDeviceInfo& d : listEglDevices()) {
        if (d.software) continue;
        try {
            createHeadlessContext(GlBackend::Egl, false, d.index);
            hardwareWorks = true;
        } catch (const GlError&) {
        }
    }
    std::unique_ptr<GlContext> context = createHeadlessContext(GlBackend::Egl, false, kAutoGlDevice);
    const GlInfo info = queryGlInfo();
    std::printf("[ devices  ] auto: %s, %s\n", context->description().c_str(), info.renderer.c_str());
    if (hardwareWorks) {
        EXPECT_FALSE(info.softwareRenderer) << info.renderer;
    }
}

TEST(GlContext, EglRejectsUnknownPlatformOverride) {
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", "wayland");
    EXPECT_THROW(createHeadlessContext(GlBackend::Egl), GlError);
}

TEST(GlContext, OsMesaCreateDestroyTwiceInARow) {
    SKIP_WITHOUT_OSMESA();
    createCheckDestroy(GlBackend::OsMesa, 0.125f, "OSMesa");
    createCheckDestroy(GlBackend::OsMesa, -8.0f, "OSMesa");
}

TEST(GlContext, DebugContextOnBothBackends) {
    for (GlBackend backend : {GlBackend::Egl, GlBackend::OsMesa}) {
        if (backend == GlBackend::OsMesa && !osMesaPresent()) continue; // the EGL half still runs
        std::unique_ptr<GlContext> context = createHeadlessContext(backend, /*debugOutput=*/true);
        GLboolean enabled = GL_FALSE;
        glGetBooleanv(GL_DEBUG_OUTPUT, &enabled);
        EXPECT_EQ(enabled, GL_TRUE) << toString(backend);
        if (backend == GlBackend::Egl) { // OSMesa has no debug-context attribute
            GLint flags = 0;
            glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
            EXPECT_NE(flags & GL_CONTEXT_FLAG_DEBUG_BIT, 0);
        }
    }
}

TEST(GlContext, ParseBackendNames) {
    EXPECT_EQ(parseGlBackend("egl"), GlBackend::Egl);
    EXPECT_EQ(parseGlBackend("osmesa"), GlBackend::OsMesa);
    EXPECT_STREQ(toString(GlBackend::OsMesa), "osmesa");
    EXPECT_THROW(parseGlBackend("vulkan"), InputError);
}

TEST_F(GlTest, InfoIsSane) {
    const GlInfo info = queryGlInfo();
    // "4.5 (Core Profile) Mesa 22.3.6", "4.6.0 NVIDIA 550.54": the version leads the string; at least 4.5.
    int major = 0, minor = 0;
    ASSERT_EQ(std::sscanf(info.version.c_str(), "%d.%d", &major, &minor), 2) << info.version;
    EXPECT_GE(major * 10 + minor, 45) << info.version;
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_FALSE(info.vendor.empty());
    EXPECT_EQ(info.glslVersion.rfind("4.", 0), 0u) << info.glslVersion;
    EXPECT_GE(info.maxTextureBufferSize, kMinTextureBufferTexels);
    EXPECT_GE(info.maxTextureSize, 4096);
    EXPECT_GE(info.maxDrawBuffers, 4);
    EXPECT_GE(info.maxColorAttachments, 4);
    EXPECT_GT(info.maxFragmentUniformComponents, 0);
    EXPECT_GT(info.queryCounterBitsSamplesPassed, 0);
    EXPECT_TRUE(info.khrDebug);
    EXPECT_TRUE(hasGlExtension("GL_ARB_texture_buffer_object_rgb32") || hasGlExtension("GL_KHR_debug"));
    EXPECT_FALSE(hasGlExtension("GL_CHCRT_no_such_extension"));
    EXPECT_NO_THROW(checkRequiredGlFeatures());
}

TEST_F(GlTest, CheckGlErrorsThrowsOnceAndNamesTheError) {
    glEnable(0x1234); // not a capability: GL_INVALID_ENUM
    try {
        checkGlErrors("bad enable");
        FAIL() << "no GlError";
    } catch (const GlError& e) {
        EXPECT_NE(std::string(e.what()).find("bad enable"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("GL_INVALID_ENUM"), std::string::npos) << e.what();
        // The fixture enables KHR_debug: the driver's own message is attached.
        EXPECT_NE(std::string(e.what()).find("debug output"), std::string::npos) << e.what();
    }
    EXPECT_NO_THROW(checkGlErrors("after"));
}

TEST_F(GlTest, DebugCallbackErrorsAreReportedEvenWhenGlGetErrorWasDrained) {
    GLuint bogus = 987654;
    glBindBuffer(GL_ARRAY_BUFFER, bogus); // never generated: GL_INVALID_OPERATION in core profile
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_INVALID_OPERATION)); // someone else drained the flag...
    EXPECT_THROW(checkGlErrors("drained"), GlError);                    // ...the callback still remembers it
    EXPECT_NO_THROW(checkGlErrors("after"));
}

} // namespace
} // namespace chcrt
