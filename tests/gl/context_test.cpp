// Headless contexts: creation and destruction on both backends and both EGL platforms, the feature check,
// and error reporting through glGetError and KHR_debug.
#include "renderer/core/error.h"
#include "renderer/gl/gl_objects.h"
#include "tests/gl/gl_test_fixture.h"

#include <chrono>
#include <cstdio>

namespace chcrt {
namespace {

using test::GlTest;

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
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", "device");
    createCheckDestroy(GlBackend::Egl, 0.5f, "device platform");
}

TEST(GlContext, EglSurfacelessPlatform) {
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", "surfaceless");
    createCheckDestroy(GlBackend::Egl, 0.5f, "surfaceless platform");
}

TEST(GlContext, EglRejectsUnknownPlatformOverride) {
    test::ScopedEnv env("CHCRT_EGL_PLATFORM", "wayland");
    EXPECT_THROW(createHeadlessContext(GlBackend::Egl), GlError);
}

TEST(GlContext, OsMesaCreateDestroyTwiceInARow) {
    createCheckDestroy(GlBackend::OsMesa, 0.125f, "OSMesa");
    createCheckDestroy(GlBackend::OsMesa, -8.0f, "OSMesa");
}

TEST(GlContext, DebugContextOnBothBackends) {
    for (GlBackend backend : {GlBackend::Egl, GlBackend::OsMesa}) {
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
    EXPECT_EQ(info.version.rfind("4.5", 0), 0u) << info.version; // "4.5 (Core Profile) Mesa ..." or "4.5.0 NVIDIA"
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
