#pragma once
// The window's input for the viewer: key presses queued by GLFW's callback (installed before Dear ImGui's backend,
// which chains to it) and handled between frames, the keys held for flying (WASD/QE, shift), mouse look with the
// right button, the scroll wheel and left clicks (the shafts view's pick). Scripts ignore real input (clear()).
#include "app/viewer/walk_controller.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

struct GLFWwindow;

namespace chcrt::app {

// One frame of interactive input.
struct InteractiveInput {
    std::vector<int> keys;     // GLFW key codes pressed since the last frame (none while ImGui has the keyboard)
    WalkInput walk;            // held keys, mouse look, scroll
    // A left click in the window (not on the panel): its position as a fraction of the window, in [0, 1).
    std::optional<std::pair<double, double>> click;
};

class WindowInput {
public:
    // Installs the key and scroll callbacks; the window's user pointer becomes this object.
    explicit WindowInput(GLFWwindow* window);
    // `keyboardTaken` / `mouseTaken`: ImGui wants them (io.WantCaptureKeyboard / WantCaptureMouse).
    InteractiveInput poll(bool keyboardTaken, bool mouseTaken);
    void clear(); // drops what was queued (scripted sessions)
    bool looking() const { return looking_; } // the right button is held for mouse look

private:
    static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void onScroll(GLFWwindow* window, double x, double y);

    GLFWwindow* window_;
    std::vector<int> pressedKeys_;
    float scrollSteps_ = 0;
    bool looking_ = false;
    bool leftWasDown_ = false;
    double lastCursorX_ = 0, lastCursorY_ = 0;
};

// The GLFW key of a script's key name (kPressableKeys, viewer_script.h); InputError for others.
int keyCodeFor(const std::string& name);

} // namespace chcrt::app
