#include "tests/gl/gl_test_fixture.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace chcrt::test {

GlBackend testBackend() {
    const char* name = std::getenv("CHCRT_TEST_GL_BACKEND");
    return name != nullptr && *name != '\0' ? parseGlBackend(name) : GlBackend::Egl;
}

void GlTest::SetUp() { context_ = createHeadlessContext(testBackend(), /*debugOutput=*/true); }

void GlTest::TearDown() {
    // A test that left a GL error behind fails here, even if its own assertions passed.
    EXPECT_NO_THROW(checkGlErrors("end of test"));
    context_.reset();
}

std::vector<glm::vec4> readTextureRgba32f(GLuint texture, int width, int height) {
    std::vector<glm::vec4> texels(static_cast<size_t>(width) * static_cast<size_t>(height));
    glGetTextureImage(texture, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(texels.size() * sizeof(glm::vec4)),
                      texels.data());
    checkGlErrors("readTextureRgba32f");
    return texels;
}

ScopedEnv::ScopedEnv(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) {
        previous_ = old;
    }
    if (value) {
        setenv(name, value->c_str(), 1);
    } else {
        unsetenv(name);
    }
}

ScopedEnv::~ScopedEnv() {
    if (previous_) {
        setenv(name_.c_str(), previous_->c_str(), 1);
    } else {
        unsetenv(name_.c_str());
    }
}

ScratchShaderDir::ScratchShaderDir(const std::map<std::string, std::string>& files) {
    // mkdtemp gives a unique directory per process, so parallel ctest runs do not collide.
    std::string pattern = (std::filesystem::temp_directory_path() / "chcrt_shaders_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
        throw std::runtime_error("mkdtemp failed");
    }
    dir_ = pattern;
    for (const auto& [relative, text] : files) {
        const std::filesystem::path file = std::filesystem::path(dir_) / relative;
        std::filesystem::create_directories(file.parent_path());
        std::ofstream(file, std::ios::binary) << text;
    }
    env_ = std::make_unique<ScopedEnv>("CHCRT_SHADER_DIR", dir_);
}

ScratchShaderDir::~ScratchShaderDir() {
    env_.reset();
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
}

} // namespace chcrt::test
