#pragma once
// Shared pieces of the GL tests: a fixture owning one headless context per test, read-back helpers, and
// scratch shader directories for the loader tests.
#include "renderer/gl/context.h"
#include "renderer/gl/gl.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace chcrt::test {

// The backend the fixture uses: EGL, or OSMesa when CHCRT_TEST_GL_BACKEND=osmesa.
GlBackend testBackend();

// One context per test, with KHR_debug errors turned into exceptions by checkGlErrors().
class GlTest : public ::testing::Test {
protected:
    void SetUp() override;
    void TearDown() override;
    std::unique_ptr<GlContext> context_;
};

// All texels of level 0 of an RGBA32F 2D texture, row by row from the bottom.
std::vector<glm::vec4> readTextureRgba32f(GLuint texture, int width, int height);

// Sets (or unsets, with nullopt) an environment variable for the lifetime of the object.
class ScopedEnv {
public:
    ScopedEnv(const char* name, std::optional<std::string> value);
    ~ScopedEnv();
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    std::string name_;
    std::optional<std::string> previous_;
};

// A fresh directory of shader files (path relative to the directory -> text), removed on destruction, and
// CHCRT_SHADER_DIR pointing at it meanwhile.
class ScratchShaderDir {
public:
    explicit ScratchShaderDir(const std::map<std::string, std::string>& files);
    ~ScratchShaderDir();
    ScratchShaderDir(const ScratchShaderDir&) = delete;
    ScratchShaderDir& operator=(const ScratchShaderDir&) = delete;
    const std::string& path() const { return dir_; }

private:
    std::string dir_;
    std::unique_ptr<ScopedEnv> env_;
};

} // namespace chcrt::test
