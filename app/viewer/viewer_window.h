#pragma once
// The viewer's window: a GLFW window with an OpenGL 4.5 core context, made current, with the GL function
// table loaded from it (glfwGetProcAddress) and the required features checked. It is the GlContext of the
// viewer's GpuSession (app/session.h), so tracing methods are created for it as for the headless commands.
#include "renderer/gl/context.h"

struct GLFWwindow;

namespace chcrt::app {

class GlfwWindowContext : public GlContext {
public:
    // Throws GlError when there is no display or no 4.5 core context.
    GlfwWindowContext(int width, int height, bool debugOutput);
    ~GlfwWindowContext() override;
    GlfwWindowContext(const GlfwWindowContext&) = delete;
    GlfwWindowContext& operator=(const GlfwWindowContext&) = delete;

    std::string description() const override { return "GLFW window"; }
    GLFWwindow* window() const { return window_; }
    // A hidden 1×1 window whose context shares objects (buffers, textures, programs) with the window's, for GPU
    // uploads on one worker thread at a time; nullptr when the platform refuses a second context (uploads then
    // run on the main thread).
    GLFWwindow* uploadWindow() const { return uploadWindow_; }

private:
    GLFWwindow* window_ = nullptr;
    GLFWwindow* uploadWindow_ = nullptr;
};

} // namespace chcrt::app
