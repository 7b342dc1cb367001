#include "app/viewer/viewer_window.h"

#include "renderer/core/error.h"
#include "renderer/gl/gl.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>

namespace chcrt::app {

GlfwWindowContext::GlfwWindowContext(int width, int height, bool debugOutput) {
    glfwSetErrorCallback(
        [](int code, const char* text) { std::fprintf(stderr, "chcrt: GLFW error %d: %s\n", code, text); });
    if (!glfwInit()) {
        throw GlError("cannot open a window: GLFW failed to initialise (no display? set DISPLAY, or run under "
                      "Xvfb: Xvfb :99 & DISPLAY=:99 chcrt view)");
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debugOutput ? GLFW_TRUE : GLFW_FALSE);
    window_ = glfwCreateWindow(width, height, "chcrt view", nullptr, nullptr);
    if (!window_) {
        glfwTerminate();
        throw GlError("cannot create a window with an OpenGL 4.5 core context");
    }
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    uploadWindow_ = glfwCreateWindow(1, 1, "chcrt upload", nullptr, window_); // shares window_'s objects
    glfwDefaultWindowHints();
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(0); // frame times are measured: no vsync
    try {
        loadGlFunctions([](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); });
        checkRequiredGlFeatures();
        if (debugOutput) enableGlDebugOutput(false);
    } catch (...) {
        if (uploadWindow_) glfwDestroyWindow(uploadWindow_);
        glfwDestroyWindow(window_);
        glfwTerminate();
        throw;
    }
}

GlfwWindowContext::~GlfwWindowContext() {
    if (uploadWindow_) glfwDestroyWindow(uploadWindow_);
    glfwDestroyWindow(window_);
    glfwTerminate();
}

} // namespace chcrt::app
