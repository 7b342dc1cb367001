// `chcrt view`: runs the viewer, build/bin/chcrt-view (app/viewer/), which lies next to this program. The viewer
// is a program of its own so that the CLI links neither GLFW nor X11 nor Dear ImGui: headless runs start without
// them. The arguments were checked by this program's parser already; chcrt-view parses the same flags again
// (addViewOptions) and replaces this process, so exit codes, output and the environment (DISPLAY) are its own.
#include "app/commands.h"

#include "renderer/core/error.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace chcrt::app {

int runView(const ViewOptions& options, const std::vector<std::string>& arguments) {
    checkViewOptions(options);
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error) throw InputError("cannot find the viewer: /proc/self/exe: " + error.message());
    const std::filesystem::path viewer = self.parent_path() / "chcrt-view";
    std::vector<std::string> words = {viewer.string()};
    words.insert(words.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    argv.push_back(nullptr);
    ::execv(viewer.c_str(), argv.data());
    throw InputError("cannot run the viewer " + viewer.string() + ": " + std::strerror(errno) +
                     " (build it: cmake --build build --target chcrt-view)");
}

} // namespace chcrt::app
