#pragma once
// Linked programs shared by everything that compiles the same stages with the same defines. A driver compiles a
// program's code per program object — llvmpipe JIT-compiles its variants at the program's first draws, about 3 ms
// for a cell pass at 256² — so objects that would each link an identical program take it from one cache and pay
// that once: the CHC+RT tracers of the adaptive choice's termination heights (culling/README.md, "Adaptive choice"),
// whose first traces otherwise each compiled the same cell pass again.
// Uniforms belong to the program, so they are shared too: a user sets the uniforms a draw reads before that draw.
#include "renderer/gl/shader.h"

#include <map>
#include <string>
#include <vector>

namespace chcrt {

class ProgramCache {
public:
    // The program of these stages and defines, compiled and linked on the first request (throws GlError as
    // ShaderProgram does, and then caches nothing). The reference stays valid as long as the cache.
    const ShaderProgram& get(const std::vector<ShaderStage>& stages, const std::vector<ShaderDefine>& defines = {});
    size_t size() const { return programs_.size(); }

private:
    std::map<std::string, ShaderProgram> programs_; // by stages and defines; a node map keeps references valid
};

} // namespace chcrt
