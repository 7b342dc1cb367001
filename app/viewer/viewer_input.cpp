#include "app/viewer/viewer_input.h"

#include "renderer/core/error.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>

namespace chcrt::app {

WindowInput::WindowInput(GLFWwindow* window) : window_(window) {
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, &WindowInput::onKey);
    glfwSetScrollCallback(window_, &WindowInput::onScroll);
}

void WindowInput::onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
    auto* self = static_cast<WindowInput*>(glfwGetWindowUserPointer(window));
    if (action == GLFW_PRESS || action == GLFW_REPEAT) self->pressedKeys_.push_back(key);
}

void WindowInput::onScroll(GLFWwindow* window, double /*x*/, double y) {
    static_cast<WindowInput*>(glfwGetWindowUserPointer(window))->scrollSteps_ += float(y);
}

void WindowInput::clear() {
    pressedKeys_.clear();
    scrollSteps_ = 0;
}

InteractiveInput WindowInput::poll(bool keyboardTaken, bool mouseTaken) {
    InteractiveInput in;
    std::vector<int> keys = std::move(pressedKeys_);
    pressedKeys_.clear();
    if (!keyboardTaken) {
        in.keys = std::move(keys);
        auto held = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS; };
        in.walk.forward = held(GLFW_KEY_W);
        in.walk.back = held(GLFW_KEY_S);
        in.walk.left = held(GLFW_KEY_A);
        in.walk.right = held(GLFW_KEY_D);
        in.walk.up = held(GLFW_KEY_E);
        in.walk.down = held(GLFW_KEY_Q);
        in.walk.fast = held(GLFW_KEY_LEFT_SHIFT) || held(GLFW_KEY_RIGHT_SHIFT);
    }
    double x = 0, y = 0;
    glfwGetCursorPos(window_, &x, &y);
    const bool rightHeld = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    if (rightHeld && (looking_ || !mouseTaken)) {
        if (looking_) in.walk.lookPixels = glm::vec2(float(x - lastCursorX_), float(y - lastCursorY_));
        looking_ = true;
    } else {
        looking_ = false;
    }
    lastCursorX_ = x;
    lastCursorY_ = y;
    const bool leftDown = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (leftDown && !leftWasDown_ && !mouseTaken) {
        int width = 1, height = 1;
        glfwGetWindowSize(window_, &width, &height);
        in.click = std::make_pair(x / std::max(width, 1), y / std::max(height, 1));
    }
    leftWasDown_ = leftDown;
    if (!mouseTaken) in.walk.scrollSteps = scrollSteps_;
    scrollSteps_ = 0;
    return in;
}

int keyCodeFor(const std::string& name) {
    if (name == "R") return GLFW_KEY_R;
    if (name == "F") return GLFW_KEY_F;
    if (name == "P") return GLFW_KEY_P;
    if (name == "V") return GLFW_KEY_V;
    if (name == "C") return GLFW_KEY_C;
    if (name == "F9") return GLFW_KEY_F9;
    if (name == "F12") return GLFW_KEY_F12;
    if (name == "+") return GLFW_KEY_EQUAL;
    if (name == "-") return GLFW_KEY_MINUS;
    if (name == "TAB") return GLFW_KEY_TAB;
    throw InputError("script: cannot press '" + name + "'");
}

} // namespace chcrt::app
