#pragma once
// The interactive walkthrough viewer (`chcrt view`, issue 6): a GLFW window with a GL 4.5 core context, the
// Renderer drawing at an internal resolution (render scale), the view modes of view_modes.h blitted to the
// window, an ImGui panel, game-style camera controls, camera-path playback and recording, screenshots and
// progressive refinement when the camera stops. Scenes load on a worker thread (viewer_session.h); the GL
// upload and shader compilation of a new scene then run on the main thread, which blocks the window for that
// step only. `--script` runs a scripted session (viewer_script.h) and returns its status. The program is
// build/bin/chcrt-view (viewer_main.cpp), which `chcrt view` runs.
//
// Keys: WASD/QE fly, right mouse button look, scroll or +/- speed, shift fast, R reset to the path's first
// camera, F frame the scene, P play/pause the path, V next view mode, C print + copy the command line,
// F9 start/stop recording (saved to --record), F12 screenshot, Tab panel, Esc quit.
#include "app/commands.h"

namespace chcrt::app {

// Runs the viewer until the window closes (or the script ends); returns the exit code (commands.h).
int runViewer(const ViewOptions& options);

} // namespace chcrt::app
