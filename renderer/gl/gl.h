#pragma once
// Include this, never <GL/gl.h>: it declares the GL 4.5 core API as a table of function pointers filled
// from the current context's own get-proc-address (EGL, OSMesa or GLFW). One loader serves all three;
// libepoxy, GLEW and glbinding work with EGL and GLX contexts but fail with OSMesa. The table is generated at
// build time from /usr/include/GL/glcorearb.h (cmake/GlLoader.cmake).
#include "gl_functions.h" // generated into the build tree

namespace chcrt {

using GlProcAddressFn = void* (*)(const char* name);

// Fills the function table from `getProcAddress`. Call once per process after a context is current (all
// contexts of one process must come from the same driver). Throws GlError when a GL 4.5 core entry point
// is missing.
void loadGlFunctions(GlProcAddressFn getProcAddress);

} // namespace chcrt
