#pragma once
// Live GL objects of the process, counted where every call of chcrt reaches GL: the function table (gl.h).
// loadGlFunctions() puts counting wrappers in the table's glGen*/glCreate*/glDelete* slots (buffers, textures,
// framebuffers, renderbuffers, vertex arrays, queries, samplers, programs, shaders, sync objects), so objects made
// outside the RAII owners of gl_objects.h (query pools, programs) are counted too. A count is what chcrt created
// minus what it deleted, over all contexts of the process; names 0 are not counted. Dear ImGui's OpenGL backend
// loads its own functions, so the viewer's panel objects are not in these counts. Long runs (scripts/soak.sh) check
// that the counts stay flat: a count that grows frame after frame is a leak.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace chcrt {

struct GlObjectCounts {
    int64_t buffers = 0, textures = 0, framebuffers = 0, renderbuffers = 0, vertexArrays = 0, queries = 0,
            samplers = 0, programs = 0, shaders = 0, syncs = 0;
    int64_t total() const {
        return buffers + textures + framebuffers + renderbuffers + vertexArrays + queries + samplers + programs +
               shaders + syncs;
    }
    // (name, count) in a fixed order, for JSON and messages: "buffers", "textures", ...
    std::vector<std::pair<std::string, int64_t>> named() const;
};

// Thread-safe (the viewer uploads on a worker with a shared context).
GlObjectCounts liveGlObjects();

namespace detail {
// Called by loadGlFunctions() after it filled the table: wraps the creating and deleting functions.
void installGlObjectCounting();
} // namespace detail

} // namespace chcrt
