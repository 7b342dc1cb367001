// Fills the generated function table (cmake/GlLoader.cmake) from a context's get-proc-address.
#include "renderer/core/error.h"
#include "renderer/gl/gl.h"
#include "renderer/gl/gl_internal.h"
#include "renderer/gl/gl_object_count.h"

#include <atomic>
#include <string>

namespace chcrt {
namespace {
std::atomic<unsigned> gLoadGeneration{0};
} // namespace

unsigned detail::glLoadGeneration() { return gLoadGeneration.load(); }

void loadGlFunctions(GlProcAddressFn getProcAddress) {
    // Every slot is rewritten, so loading again for a new context never keeps a pointer of the previous one.
    // A non-NULL pointer proves nothing for extensions (Mesa and glvnd hand out dispatch stubs for any name);
    // only the required core functions are checked here, and extensions are tested by name elsewhere.
    std::string missing;
    int missingCount = 0;
    for (unsigned i = 0; i < gl::kFunctionCount; ++i) {
        const gl::FunctionEntry& entry = gl::kFunctionTable[i];
        *entry.slot = getProcAddress(entry.name);
        if (*entry.slot == nullptr && entry.requiredCore45 != 0) {
            // Functions promoted to core keep the ARB extension's semantics, and some drivers export only the
            // suffixed name: Mesa 22.3's OSMesa returns NULL for glGetnTexImage, glGetnCompressedTexImage and
            // glGetnUniformdv (GL 4.5, from ARB_robustness) but has their ARB versions.
            *entry.slot = getProcAddress((std::string(entry.name) + "ARB").c_str());
        }
        if (*entry.slot == nullptr && entry.requiredCore45 != 0) {
            if (missingCount < 8) {
                missing += std::string(missingCount == 0 ? "" : ", ") + entry.name + " (" + entry.section + ")";
            }
            ++missingCount;
        }
    }
    detail::installGlObjectCounting(); // live object counts (gl_object_count.h)
    ++gLoadGeneration;
    if (missingCount > 0) {
        throw GlError("GL loader: " + std::to_string(missingCount) +
                      " required OpenGL 4.5 core functions are missing: " + missing +
                      (missingCount > 8 ? ", ..." : "") + " (is the context current and 4.5 core?)");
    }
}

} // namespace chcrt
