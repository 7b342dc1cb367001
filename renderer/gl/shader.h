#pragma once
// Shader loading: sources live in shaders/ and are embedded into the binary at build time (so build/bin/chcrt
// runs from anywhere); CHCRT_SHADER_DIR=<dir> loads them from disk instead (the viewer's reload key uses it).
// The loader pastes #include "..." (paths relative to shaders/, include guards honoured via #pragma once or
// #ifndef), keeps #version first, inserts the variant #defines after it and emits #line directives so that
// compile errors are reported with the real file name and line. `#include NAME` pastes the file a define names:
// a variant define whose value is a quoted path ({"CHCRT_BVH_TRAVERSAL", "\"linespace/linespace_traverse.glsl\""}),
// else the shader's own `#define NAME "path"` (its default). So a pass can take a traversal from a library above
// its own without naming it: the dependency points from the extension to the pass.
#include "renderer/gl/gl.h"

#include <glm/glm.hpp>

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace chcrt {

struct ShaderDefine {
    std::string name;
    std::string value; // may be empty
};

struct ShaderStage {
    GLenum type;      // GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER
    std::string path; // relative to shaders/, e.g. "render/trace_bvh.frag.glsl"
};

// Preprocessed source of one stage, and the table mapping GLSL source-string numbers (used in #line) to
// file paths. Throws GlError for a missing file or include cycle.
struct PreprocessedShader {
    std::string text;
    std::vector<std::string> files; // index = source-string number in #line directives
};
PreprocessedShader preprocessShader(const std::string& path, const std::vector<ShaderDefine>& defines);

// Rewrites a driver's compile log ("0:12(5): error ..." Mesa, "0(12) : error ..." NVIDIA) so that
// source-string numbers become file names: "render/trace_bvh.frag.glsl:12(5): error ...".
std::string mapShaderLog(const std::string& log, const std::vector<std::string>& files);

// The defines every program gets besides its own (its own value wins where it names one), appended after them:
//   CHCRT_TRACE_LOOP_CAP 0 | 1: whether the current context's renderer needs the loop cap (currentRendererTraits(),
//     renderer/gl/context.h; shaders/shared/render_layout.h says what it compiles in);
//   the process-wide ones set with setProcessShaderDefine: CHCRT_TRIANGLE_BUFFERS (renderer/render/scene_gpu.h).
std::vector<ShaderDefine> withImplicitDefines(const std::vector<ShaderDefine>& own);
// Sets a define for every program compiled from now on, on any context (an empty value unsets it).
void setProcessShaderDefine(const std::string& name, const std::string& value);
// Its value, "" when unset.
std::string processShaderDefine(const std::string& name);

// CHCRT_SHADER_DUMP_DIR=<dir>: every stage compiled is also written there, preprocessed with all its defines, as
// <hash>.<vert|frag|comp> (a first comment line names its file): what tests/gl/glslang_test.cpp gives a strict
// compiler, glslangValidator.

// A linked program. Move-only; deletes the GL object on destruction. Uniform locations are cached.
class ShaderProgram {
public:
    ShaderProgram() = default;
    // Compiles and links; throws GlError carrying the mapped compile/link log.
    ShaderProgram(const std::vector<ShaderStage>& stages, const std::vector<ShaderDefine>& defines = {});
    ~ShaderProgram();
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;

    GLuint id() const { return program_; }
    bool valid() const { return program_ != 0; }
    void use() const;
    // -1 when the uniform does not exist or was optimised away (setting it is then a no-op).
    GLint uniformLocation(const std::string& name) const;

    void set(const std::string& name, int value) const;
    void set(const std::string& name, unsigned value) const;
    void set(const std::string& name, float value) const;
    void set(const std::string& name, const glm::vec2& value) const;
    void set(const std::string& name, const glm::vec3& value) const;
    void set(const std::string& name, const glm::vec4& value) const;
    void set(const std::string& name, const glm::ivec2& value) const;
    void set(const std::string& name, const glm::uvec2& value) const;
    void set(const std::string& name, const glm::mat4& value) const;
    void setArray(const std::string& name, const glm::vec4* values, int count) const;
    void setArray(const std::string& name, const glm::uvec4* values, int count) const;

private:
    GLuint program_ = 0;
    mutable std::unordered_map<std::string, GLint> uniformCache_;
};

} // namespace chcrt
