#pragma once
// Internal to chcrt_gl: what the context backends and the loader share. Not for use outside renderer/gl/.
#include "renderer/gl/context.h"

#include <memory>

namespace chcrt::detail {

// Same type as GlProcAddressFn (gl.h), repeated here so that context_osmesa.cpp, which must not include gl.h
// (<GL/osmesa.h> pulls in <GL/gl.h>), can name it.
using ProcLoader = void* (*)(const char* name);

// A headless context that is current on the calling thread; the GL functions are not loaded yet.
class HeadlessContext : public GlContext {
public:
    virtual ProcLoader procLoader() const = 0;
};

// Each throws GlError with a one-line actionable message when no 4.5 core context can be made current.
std::unique_ptr<HeadlessContext> createEglContext(bool debugContext, int device);
std::unique_ptr<HeadlessContext> createOsMesaContext(bool debugContext);

// Incremented by every loadGlFunctions() call, i.e. once per context a caller starts using. Objects cached per
// context (the fullscreen VAO) compare it to notice that their context has been replaced.
unsigned glLoadGeneration();

} // namespace chcrt::detail
