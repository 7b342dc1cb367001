// build/bin/chcrt-view: the interactive viewer as a program of its own (`chcrt view` runs it, app/command_view.cpp),
// so that only it links GLFW, X11 and Dear ImGui. Same flags, messages and exit codes as `chcrt view`.
#include "app/commands.h"
#include "app/viewer/viewer_app.h"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
    using namespace chcrt::app;
    return runReportingErrors([&] {
        CLI::App cli{"chcrt view: interactive walkthrough viewer (GLFW window, ImGui panel)", "chcrt view"};
        ViewOptions view;
        addViewOptions(cli, view);
        if (const std::optional<int> exit = parseCommandLine(cli, argc, argv)) return *exit;
        checkViewOptions(view);
        return runViewer(view);
    });
}
