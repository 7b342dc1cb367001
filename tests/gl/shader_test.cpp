// Shader loader: #include pasting, #line numbering, source lookup (embedded and CHCRT_SHADER_DIR), log mapping,
// and compile/link errors that name the right file and line.
#include "renderer/core/error.h"
#include "renderer/gl/program_cache.h"
#include "renderer/gl/shader.h"
#include "tests/gl/gl_test_fixture.h"

#include <cctype>
#include <functional>
#include <map>

namespace chcrt {
namespace {

using test::GlTest;
using test::ScratchShaderDir;

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const GlError& e) {
        return e.what();
    }
    return "(no GlError)";
}

TEST(ShaderPreprocess, VersionFirstThenDefinesThenNumberedFiles) {
    ScratchShaderDir dir({
        {"main.frag.glsl", "// comment before version\n#version 450 core\n#include \"lib/a.glsl\"\nvoid main() {}\n"},
        {"lib/a.glsl", "#include \"b.glsl\"\nfloat a;\n"}, // b.glsl: not in the root, so relative to lib/
        {"lib/b.glsl", "float b;\n"},
    });
    const PreprocessedShader result = preprocessShader("main.frag.glsl", {{"FOO", "1"}, {"BAR", ""}});
    EXPECT_EQ(result.text, "#version 450 core\n"
                           "#define FOO 1\n"
                           "#define BAR\n"
                           "#line 1 0\n"
                           "// comment before version\n"
                           "\n"
                           "#line 1 1\n"
                           "#line 1 2\n"
                           "float b;\n"
                           "#line 2 1\n"
                           "float a;\n"
                           "#line 4 0\n"
                           "void main() {}\n");
    EXPECT_EQ(result.files, (std::vector<std::string>{"main.frag.glsl", "lib/a.glsl", "lib/b.glsl"}));
}

TEST(ShaderPreprocess, RootRelativePathsWinAndDotDotIsResolved) {
    ScratchShaderDir dir({
        {"main.glsl", "#version 450 core\n#include \"lib/a.glsl\"\n"},
        {"lib/a.glsl", "#include \"b.glsl\"\n#include \"../lib/./c.glsl\"\n"},
        {"b.glsl", "float rootB;\n"},
        {"lib/b.glsl", "float libB;\n"},
        {"lib/c.glsl", "float c;\n"},
    });
    const PreprocessedShader result = preprocessShader("main.glsl", {});
    EXPECT_NE(result.text.find("rootB"), std::string::npos);
    EXPECT_EQ(result.text.find("libB"), std::string::npos);
    EXPECT_EQ(result.files, (std::vector<std::string>{"main.glsl", "lib/a.glsl", "b.glsl", "lib/c.glsl"}));
}

TEST(ShaderPreprocess, RepeatedIncludesArePastedEachTimeUnlessPragmaOnce) {
    ScratchShaderDir dir({
        {"main.glsl", "#version 450 core\n#include \"begin.h\"\n#include \"begin.h\"\n"
                      "#include \"once.h\"\n#include \"once.h\"\n"},
        {"begin.h", "// BEGIN\n"},
        {"once.h", "#pragma once\n// ONCE\n"},
    });
    const PreprocessedShader result = preprocessShader("main.glsl", {});
    auto count = [&](const std::string& needle) {
        int n = 0;
        for (size_t pos = result.text.find(needle); pos != std::string::npos; pos = result.text.find(needle, pos + 1)) {
            ++n;
        }
        return n;
    };
    EXPECT_EQ(count("// BEGIN"), 2); // shared_begin.h must open the namespace at every use
    EXPECT_EQ(count("// ONCE"), 1);
    EXPECT_EQ(result.files.size(), 3u); // one source-string number per file, however often it is pasted
}

TEST(ShaderPreprocess, IncludeCycleThrowsWithTheChain) {
    ScratchShaderDir dir({
        {"main.glsl", "#version 450 core\n#include \"a.glsl\"\n"},
        {"a.glsl", "#include \"b.glsl\"\n"},
        {"b.glsl", "\n#include \"a.glsl\"\n"},
    });
    const std::string message = errorOf([] { preprocessShader("main.glsl", {}); });
    EXPECT_NE(message.find("cycle: main.glsl -> a.glsl -> b.glsl -> a.glsl (at b.glsl:2)"), std::string::npos)
        << message;
}

TEST(ShaderPreprocess, MissingFilesThrowNamingTheIncluder) {
    ScratchShaderDir dir({
        {"main.glsl", "#version 450 core\n\n#include \"nowhere.glsl\"\n"},
        {"lib/escape.glsl", "#include \"../../outside.glsl\"\n"},
    });
    const std::string missingInclude = errorOf([] { preprocessShader("main.glsl", {}); });
    EXPECT_NE(missingInclude.find("\"nowhere.glsl\" (from main.glsl:3) not found"), std::string::npos)
        << missingInclude;
    const std::string missingRoot = errorOf([] { preprocessShader("absent.frag.glsl", {}); });
    EXPECT_NE(missingRoot.find("absent.frag.glsl"), std::string::npos) << missingRoot;
    EXPECT_NE(missingRoot.find("CHCRT_SHADER_DIR=" + dir.path()), std::string::npos) << missingRoot;
    EXPECT_THROW(preprocessShader("lib/escape.glsl", {}), GlError); // paths cannot leave shaders/
}

TEST(ShaderPreprocess, IncludeByNameTakesTheHostsPathElseTheFilesDefault) {
    ScratchShaderDir dir({
        {"main.glsl", "#version 450 core\n#ifndef TRAVERSAL\n#define TRAVERSAL \"pure.glsl\"\n#endif\n"
                      "#include TRAVERSAL\nvoid main() {}\n"},
        {"pure.glsl", "float pure;\n"},
        {"ext/other.glsl", "float other;\n"},
        {"unnamed.glsl", "#version 450 core\n#include NOWHERE\n"},
    });
    const PreprocessedShader byDefault = preprocessShader("main.glsl", {{"FOO", "1"}});
    EXPECT_NE(byDefault.text.find("float pure;"), std::string::npos) << byDefault.text;
    EXPECT_EQ(byDefault.text.find('"'), std::string::npos) << "quoted paths must not reach GLSL: " << byDefault.text;
    EXPECT_NE(byDefault.text.find("#define FOO 1\n"), std::string::npos);
    const PreprocessedShader byHost = preprocessShader("main.glsl", {{"TRAVERSAL", "\"ext/other.glsl\""}});
    EXPECT_NE(byHost.text.find("float other;"), std::string::npos) << byHost.text;
    EXPECT_EQ(byHost.text.find("float pure;"), std::string::npos) << byHost.text;
    EXPECT_EQ(byHost.text.find('"'), std::string::npos) << byHost.text;
    EXPECT_EQ(byHost.files, (std::vector<std::string>{"main.glsl", "ext/other.glsl"}));
    const std::string unnamed = errorOf([] { preprocessShader("unnamed.glsl", {}); });
    EXPECT_NE(unnamed.find("#include NOWHERE at unnamed.glsl:2"), std::string::npos) << unnamed;
    EXPECT_THROW(preprocessShader("main.glsl", {{"TRAVERSAL", "\"unterminated"}}), GlError);
}

TEST(ShaderPreprocess, EmbeddedTableServesTheRepositoryShaders) {
    test::ScopedEnv env("CHCRT_SHADER_DIR", std::nullopt);
    const PreprocessedShader twin = preprocessShader("test/intersect_twin.frag.glsl", {});
    EXPECT_EQ(twin.text.rfind("#version 450 core\n", 0), 0u);
    EXPECT_EQ(twin.files, (std::vector<std::string>{"test/intersect_twin.frag.glsl", "shared/intersect.h",
                                                    "shared/shared_begin.h", "shared/shared_end.h"}));
    EXPECT_NE(twin.text.find("intersectRayTriangle"), std::string::npos);
    const std::string missing = errorOf([] { preprocessShader("test/absent.frag.glsl", {}); });
    EXPECT_NE(missing.find("embedded"), std::string::npos) << missing;
}

TEST(ShaderLog, MapsMesaNvidiaAndGlslangFormats) {
    const std::vector<std::string> files = {"render/trace_bvh.frag.glsl", "shared/intersect.h"};
    EXPECT_EQ(mapShaderLog("0:12(5): error: `x' undeclared\n1:3(10): warning: unused\n", files),
              "render/trace_bvh.frag.glsl:12(5): error: `x' undeclared\nshared/intersect.h:3(10): warning: unused\n");
    EXPECT_EQ(mapShaderLog("1(42) : error C1008: undefined variable \"y\"\n", files),
              "shared/intersect.h:42: error C1008: undefined variable \"y\"\n");
    EXPECT_EQ(mapShaderLog("ERROR: 1:7: 'z' : undeclared identifier\n", files),
              "ERROR: shared/intersect.h:7: 'z' : undeclared identifier\n");
    // Unknown source strings and other lines stay as they are.
    EXPECT_EQ(mapShaderLog("7:1(1): error: odd\nlink failed\n", files), "7:1(1): error: odd\nlink failed\n");
}

// Whether a mapped compile log names `file` at `line`, in any driver's format after mapping: Mesa's
// "file:12(5): error", NVIDIA's "file:12: error", glslang's "ERROR: file:12: ...".
bool namesFileLine(const std::string& log, const std::string& file, int line) {
    const std::string key = file + ":" + std::to_string(line);
    for (size_t at = log.find(key); at != std::string::npos; at = log.find(key, at + 1)) {
        const size_t after = at + key.size();
        if (after == log.size() || !std::isdigit(static_cast<unsigned char>(log[after]))) return true;
    }
    return false;
}

TEST(ShaderLog, NamesFileLineAcceptsEveryDriversFormat) {
    EXPECT_TRUE(namesFileLine("lib/bad.glsl:4(5): error: x", "lib/bad.glsl", 4));
    EXPECT_TRUE(namesFileLine("lib/bad.glsl:4: error C1008: x", "lib/bad.glsl", 4));
    EXPECT_TRUE(namesFileLine("ERROR: lib/bad.glsl:4: 'x' : undeclared", "lib/bad.glsl", 4));
    EXPECT_FALSE(namesFileLine("lib/bad.glsl:41: error", "lib/bad.glsl", 4));
    EXPECT_FALSE(namesFileLine("other.glsl:4: error", "lib/bad.glsl", 4));
}

// A program whose only stage is `main.frag.glsl` from a scratch directory; returns the GlError message.
std::string compileError(const std::map<std::string, std::string>& files) {
    ScratchShaderDir dir(files);
    return errorOf([] { ShaderProgram program({{GL_FRAGMENT_SHADER, "main.frag.glsl"}}); });
}

const char* kMain = "#version 450 core\n"
                    "// line 2\n"
                    "#include \"lib/helpers.glsl\"\n"
                    "#include \"lib/bad.glsl\"\n"
                    "layout(location = 0) out vec4 colour;\n"
                    "void main() { colour = vec4(helper()); }\n";
const char* kHelpers = "#include \"constants.glsl\"\nfloat helper() { return kOne; }\n";
const char* kConstants = "const float kOne = 1.0f;\n";

TEST_F(GlTest, CompileErrorInIncludedFileNamesThatFileAndLine) {
    const std::string message = compileError({
        {"main.frag.glsl", kMain},
        {"lib/helpers.glsl", kHelpers},
        {"lib/constants.glsl", kConstants},
        {"lib/bad.glsl", "// bad.glsl\n\nfloat fine() { return 1.0f; }\nfloat broken() { return undefinedThing; }\n"},
    });
    EXPECT_NE(message.find("main.frag.glsl"), std::string::npos) << message;
    EXPECT_TRUE(namesFileLine(message, "lib/bad.glsl", 4)) << message;
    EXPECT_NE(message.find("undefinedThing"), std::string::npos) << message;
}

TEST_F(GlTest, CompileErrorAfterIncludesNamesTheRootLine) {
    std::string main = kMain;
    main += "float late() { return alsoUndefined; }\n"; // line 7 of main.frag.glsl
    const std::string message = compileError({
        {"main.frag.glsl", main},
        {"lib/helpers.glsl", kHelpers},
        {"lib/constants.glsl", kConstants},
        {"lib/bad.glsl", "float fine() { return 1.0f; }\n"},
    });
    EXPECT_TRUE(namesFileLine(message, "main.frag.glsl", 7)) << message;
}

TEST_F(GlTest, CompileErrorAfterSkippedConditionalIncludeKeepsLineNumbers) {
    // The compiler skips the pasted file *and* the #line that follows it; the loader re-syncs after #endif.
    const std::string message = compileError({
        {"main.frag.glsl", "#version 450 core\n#ifdef NOT_DEFINED\n#include \"long.glsl\"\n#endif\n"
                           "layout(location = 0) out vec4 colour;\n"
                           "void main() { colour = vec4(missingName); }\n"},
        {"long.glsl", "float a;\nfloat b;\nfloat c;\nfloat d;\n"},
    });
    EXPECT_TRUE(namesFileLine(message, "main.frag.glsl", 6)) << message;
}

TEST_F(GlTest, LinkErrorNamesAllStages) {
    ScratchShaderDir dir({
        {"a.vert.glsl", "#version 450 core\nout vec2 value;\nvoid main() { value = vec2(0); gl_Position = vec4(0); }\n"},
        {"b.frag.glsl", "#version 450 core\nin vec3 value;\nout vec4 colour;\nvoid main() { colour = vec4(value, 1); }\n"},
    });
    const std::string message = errorOf(
        [] { ShaderProgram program({{GL_VERTEX_SHADER, "a.vert.glsl"}, {GL_FRAGMENT_SHADER, "b.frag.glsl"}}); });
    EXPECT_NE(message.find("link"), std::string::npos) << message;
    EXPECT_NE(message.find("a.vert.glsl + b.frag.glsl"), std::string::npos) << message;
}

TEST_F(GlTest, MissingShaderFileThrows) {
    test::ScopedEnv env("CHCRT_SHADER_DIR", std::nullopt);
    EXPECT_THROW(ShaderProgram({{GL_FRAGMENT_SHADER, "test/absent.frag.glsl"}}), GlError);
}

TEST_F(GlTest, ProgramsMoveAndIgnoreUnknownUniforms) {
    test::ScopedEnv env("CHCRT_SHADER_DIR", std::nullopt);
    ShaderProgram program({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                           {GL_FRAGMENT_SHADER, "test/solid_colour.frag.glsl"}});
    EXPECT_GE(program.uniformLocation("colour"), 0);
    EXPECT_EQ(program.uniformLocation("noSuchUniform"), -1);
    program.set("noSuchUniform", 1.0f); // a no-op by the GL spec, not an error
    const GLuint id = program.id();
    ShaderProgram moved = std::move(program);
    EXPECT_FALSE(program.valid()); // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(moved.id(), id);
    EXPECT_EQ(glIsProgram(id), GL_TRUE);
    moved = ShaderProgram();
    EXPECT_EQ(glIsProgram(id), GL_FALSE);
    checkGlErrors("programs");
}

TEST_F(GlTest, ProgramCacheLinksEachStagesAndDefinesOnce) {
    test::ScopedEnv env("CHCRT_SHADER_DIR", std::nullopt);
    const std::vector<ShaderStage> stages = {{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                             {GL_FRAGMENT_SHADER, "test/solid_colour.frag.glsl"}};
    ProgramCache cache;
    const ShaderProgram& a = cache.get(stages, {{"VARIANT", "1"}});
    const ShaderProgram& b = cache.get(stages, {{"VARIANT", "2"}});
    const ShaderProgram& plain = cache.get(stages);
    EXPECT_NE(a.id(), b.id());
    EXPECT_NE(a.id(), plain.id());
    EXPECT_EQ(cache.size(), 3u);
    // The same request again: the same linked program, at the same address (references stay valid as it grows).
    EXPECT_EQ(&cache.get(stages, {{"VARIANT", "1"}}), &a);
    EXPECT_EQ(&cache.get(stages), &plain);
    EXPECT_EQ(cache.size(), 3u);
    // A stage list that differs only in its fragment shader is another program.
    const ShaderProgram& other =
        cache.get({stages[0], {GL_FRAGMENT_SHADER, "test/define_colour.frag.glsl"}}, {{"RED", "1.0"}, {"GREEN", "0.0"}});
    EXPECT_NE(other.id(), plain.id());
    // A failed compile caches nothing and throws as ShaderProgram does.
    EXPECT_THROW(cache.get({{GL_FRAGMENT_SHADER, "test/absent.frag.glsl"}}), GlError);
    EXPECT_EQ(cache.size(), 4u);
    checkGlErrors("program cache");
}

} // namespace
} // namespace chcrt
