// ShaderProgram: compiles preprocessed stages (shader_preprocess.cpp), links, and sets uniforms through DSA
// (glProgramUniform*), so setting a uniform never disturbs the bound program.
#include "renderer/gl/shader.h"

#include "renderer/core/error.h"
#include "renderer/gl/context.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>

namespace chcrt {
namespace {

const char* stageName(GLenum type) {
    switch (type) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_FRAGMENT_SHADER: return "fragment";
    case GL_COMPUTE_SHADER: return "compute";
    case GL_GEOMETRY_SHADER: return "geometry";
    case GL_TESS_CONTROL_SHADER: return "tess-control";
    case GL_TESS_EVALUATION_SHADER: return "tess-evaluation";
    default: return "unknown";
    }
}

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

std::string programLog(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

struct ProcessDefines {
    std::mutex mutex;
    std::vector<ShaderDefine> defines;
};
ProcessDefines& processDefines() {
    static ProcessDefines state;
    return state;
}

const char* dumpExtension(GLenum type) {
    switch (type) {
    case GL_VERTEX_SHADER: return "vert";
    case GL_FRAGMENT_SHADER: return "frag";
    case GL_COMPUTE_SHADER: return "comp";
    case GL_GEOMETRY_SHADER: return "geom";
    case GL_TESS_CONTROL_SHADER: return "tesc";
    case GL_TESS_EVALUATION_SHADER: return "tese";
    default: return "glsl";
    }
}

// CHCRT_SHADER_DUMP_DIR (shader.h): the stage's preprocessed text, named by its hash so a variant compiled many
// times is written once.
void dumpStage(const ShaderStage& stage, const std::string& text) {
    const char* dir = std::getenv("CHCRT_SHADER_DUMP_DIR");
    if (dir == nullptr || *dir == '\0') return;
    uint64_t hash = 1469598103934665603ull; // FNV-1a
    for (unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.", static_cast<unsigned long long>(hash));
    const std::filesystem::path file = std::filesystem::path(dir) / (name + std::string(dumpExtension(stage.type)));
    std::error_code error;
    if (std::filesystem::exists(file, error)) return;
    std::ofstream out(file, std::ios::binary);
    out << "// " << stage.path << "\n" << text;
}

// Compiles one stage; throws GlError naming the stage's file, the whole program and the mapped log.
GLuint compileStage(const ShaderStage& stage, const std::vector<ShaderDefine>& defines,
                    const std::string& programName) {
    const PreprocessedShader source = preprocessShader(stage.path, defines);
    dumpStage(stage, source.text);
    const GLuint shader = glCreateShader(stage.type);
    if (shader == 0) {
        throw GlError("glCreateShader(" + std::string(stageName(stage.type)) + ") failed for " + stage.path);
    }
    const char* text = source.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = mapShaderLog(shaderLog(shader), source.files);
        glDeleteShader(shader);
        throw GlError("failed to compile " + std::string(stageName(stage.type)) + " shader " + stage.path +
                      " (program " + programName + "):\n" + log);
    }
    return shader;
}

} // namespace

std::vector<ShaderDefine> withImplicitDefines(const std::vector<ShaderDefine>& own) {
    std::vector<ShaderDefine> all = own;
    const auto addUnlessNamed = [&all, &own](const ShaderDefine& define) {
        for (const ShaderDefine& d : own) {
            if (d.name == define.name) return;
        }
        all.push_back(define);
    };
    addUnlessNamed({"CHCRT_TRACE_LOOP_CAP", currentRendererTraits().loopCap ? "1" : "0"});
    ProcessDefines& process = processDefines();
    std::lock_guard<std::mutex> lock(process.mutex);
    for (const ShaderDefine& define : process.defines) addUnlessNamed(define);
    return all;
}

void setProcessShaderDefine(const std::string& name, const std::string& value) {
    ProcessDefines& process = processDefines();
    std::lock_guard<std::mutex> lock(process.mutex);
    std::erase_if(process.defines, [&name](const ShaderDefine& d) { return d.name == name; });
    if (!value.empty()) process.defines.push_back({name, value});
}

std::string processShaderDefine(const std::string& name) {
    ProcessDefines& process = processDefines();
    std::lock_guard<std::mutex> lock(process.mutex);
    for (const ShaderDefine& d : process.defines) {
        if (d.name == name) return d.value;
    }
    return "";
}

ShaderProgram::ShaderProgram(const std::vector<ShaderStage>& stages, const std::vector<ShaderDefine>& ownDefines) {
    const std::vector<ShaderDefine> defines = withImplicitDefines(ownDefines);
    std::string programName;
    for (const ShaderStage& stage : stages) {
        programName += (programName.empty() ? "" : " + ") + stage.path;
    }
    std::vector<GLuint> shaders;
    try {
        for (const ShaderStage& stage : stages) {
            shaders.push_back(compileStage(stage, defines, programName));
        }
    } catch (...) {
        for (GLuint shader : shaders) {
            glDeleteShader(shader);
        }
        throw;
    }
    program_ = glCreateProgram();
    for (GLuint shader : shaders) {
        glAttachShader(program_, shader);
    }
    glLinkProgram(program_);
    // The program keeps the compiled code; the shader objects are no longer needed once linked.
    for (GLuint shader : shaders) {
        glDetachShader(program_, shader);
        glDeleteShader(shader);
    }
    GLint ok = GL_FALSE;
    glGetProgramiv(program_, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = programLog(program_);
        glDeleteProgram(program_);
        program_ = 0;
        throw GlError("failed to link program " + programName + ":\n" + log);
    }
}

ShaderProgram::~ShaderProgram() {
    if (program_ != 0) {
        glDeleteProgram(program_);
    }
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : program_(std::exchange(other.program_, 0)), uniformCache_(std::move(other.uniformCache_)) {
    other.uniformCache_.clear();
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    if (this != &other) {
        if (program_ != 0) {
            glDeleteProgram(program_);
        }
        program_ = std::exchange(other.program_, 0);
        uniformCache_ = std::move(other.uniformCache_);
        other.uniformCache_.clear();
    }
    return *this;
}

void ShaderProgram::use() const { glUseProgram(program_); }

GLint ShaderProgram::uniformLocation(const std::string& name) const {
    auto it = uniformCache_.find(name);
    if (it != uniformCache_.end()) {
        return it->second;
    }
    const GLint location = program_ != 0 ? glGetUniformLocation(program_, name.c_str()) : -1;
    uniformCache_.emplace(name, location);
    return location;
}

// A location of -1 makes glProgramUniform* a silent no-op (GL spec), which is the documented behaviour for
// uniforms the compiler optimised away.
void ShaderProgram::set(const std::string& name, int value) const {
    glProgramUniform1i(program_, uniformLocation(name), value);
}
void ShaderProgram::set(const std::string& name, unsigned value) const {
    glProgramUniform1ui(program_, uniformLocation(name), value);
}
void ShaderProgram::set(const std::string& name, float value) const {
    glProgramUniform1f(program_, uniformLocation(name), value);
}
void ShaderProgram::set(const std::string& name, const glm::vec2& value) const {
    glProgramUniform2fv(program_, uniformLocation(name), 1, glm::value_ptr(value));
}
void ShaderProgram::set(const std::string& name, const glm::vec3& value) const {
    glProgramUniform3fv(program_, uniformLocation(name), 1, glm::value_ptr(value));
}
void ShaderProgram::set(const std::string& name, const glm::vec4& value) const {
    glProgramUniform4fv(program_, uniformLocation(name), 1, glm::value_ptr(value));
}
void ShaderProgram::set(const std::string& name, const glm::ivec2& value) const {
    glProgramUniform2iv(program_, uniformLocation(name), 1, glm::value_ptr(value));
}
void ShaderProgram::set(const std::string& name, const glm::uvec2& value) const {
    glProgramUniform2uiv(program_, uniformLocation(name), 1, glm::value_ptr(value));
}
void ShaderProgram::set(const std::string& name, const glm::mat4& value) const {
    glProgramUniformMatrix4fv(program_, uniformLocation(name), 1, GL_FALSE, glm::value_ptr(value));
}
void ShaderProgram::setArray(const std::string& name, const glm::vec4* values, int count) const {
    glProgramUniform4fv(program_, uniformLocation(name), count, glm::value_ptr(values[0]));
}
void ShaderProgram::setArray(const std::string& name, const glm::uvec4* values, int count) const {
    glProgramUniform4uiv(program_, uniformLocation(name), count, glm::value_ptr(values[0]));
}

} // namespace chcrt
