// `chcrt view` in a build without the viewer (CHCRT_BUILD_VIEWER=OFF): a clear message and exit code 2.
#include "app/commands.h"

#include <cstdio>

namespace chcrt::app {

int runView(const ViewOptions& /*options*/, const std::vector<std::string>& /*arguments*/) {
    std::fprintf(stderr, "chcrt: error: this build has no viewer (configure with -DCHCRT_BUILD_VIEWER=ON, which "
                         "needs GLFW 3.3 and Dear ImGui)\n");
    return kExitBadInput;
}

} // namespace chcrt::app
