// A strict compiler over every shader variant the program compiles: build/bin/chcrt runs every tracing method, ray
// type, shader stage, G-buffer kind, CHC+RT option and debug image, and the out-of-core path, on tiny scenes with
// CHCRT_SHADER_DUMP_DIR set (renderer/gl/shader.h), so each stage it compiles is written out preprocessed with all
// its defines; glslangValidator (Khronos' reference front end, Debian package glslang-tools) then validates each
// one, and each once more with the other value of CHCRT_TRACE_LOOP_CAP (the variant of the other kind of renderer).
// Every embedded stage file must have been compiled by some run; the viewer's and the tests' own shaders, which
// these commands do not compile, are validated from the embedded sources. llvmpipe accepts what a strict compiler
// may refuse (implicit conversions, missing qualifiers): this is where such errors show before a GPU run.
#include "renderer/gl/shader.h"
#include "shaders/embedded_shaders.h"
#include "tests/app/cli_fixture.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>

namespace chcrt::clitest {
namespace {

// glslangValidator's path, or "" when it is not installed.
std::string findGlslang() {
    const char* path = std::getenv("PATH");
    std::istringstream dirs(path != nullptr ? path : "");
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        const fs::path candidate = fs::path(dir) / "glslangValidator";
        if (!dir.empty() && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    return "";
}

// Runs glslangValidator on files, each compiled on its own (no -l); empty when all validate, else its output
// (which names each file before its errors).
std::string validate(const std::string& glslang, const std::vector<fs::path>& files) {
    std::string command = "'" + glslang + "'";
    for (const fs::path& file : files) command += " '" + file.string() + "'";
    command += " 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return "cannot run " + command;
    std::string output;
    std::array<char, 4096> buffer;
    while (size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
    const int status = ::pclose(pipe);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? "" : output;
}

std::string stageExtension(const std::string& path) {
    for (const char* ext : {"vert", "frag", "comp"}) {
        if (path.size() > 10 && path.compare(path.size() - 10, 10, std::string(".") + ext + ".glsl") == 0) return ext;
    }
    return "";
}

TEST_F(CliTest, GlslangValidatesEveryShaderVariantTheProgramCompiles) {
    const std::string glslang = findGlslang();
    if (glslang.empty()) {
        GTEST_SKIP() << "glslangValidator is not installed (Debian package glslang-tools, which scripts/setup.sh "
                        "installs): the strict-compiler check of the shaders is skipped";
    }
    const std::string env = "CHCRT_SHADER_DUMP_DIR=dump";
    fs::create_directories(dir_ / "dump");
    const std::string scene = "--scene city:4k --width 24 --height 16 --frames 0 --spp 1 -q --ls-cache cache ";
    const std::string all = "--ray-type primary,shadow,ao,diffuse --runs 1 --warmup 0 ";
    std::vector<std::string> commands = {
        // Every GPU method in the fragment stage (bench's image comparison renders shaded frames), traversal steps.
        // A depth-2 N-tree compiles the same passes as the default depth 3, whose build takes 16 s here.
        "bench " + scene + all + "--steps --shader-stage fragment --ls-ntree 6:2 --method bvh,chcrt,chcrt-noadapt,"
                                 "chcrt-aggressive,bvh+ls-exact,chcrt+ls-exact,bvh+ls,chcrt+ls,ntree+ls",
        // The compute stage, traced primary visibility.
        "bench " + scene + all + "--shader-stage compute --primary traced --method bvh,chcrt",
        // CHC+RT's compute cell passes over the GPU's lists.
        "bench " + scene + all + "--shader-stage compute --method chcrt-noadapt --chcrt-queries bounds-gpu",
        // CHC+RT's query kinds and options.
        "bench " + scene + all + "--method chcrt-noadapt --chcrt-queries gl --chcrt-leaf-cache on --chcrt-merged-batch off",
        "bench " + scene + all + "--method chcrt-noadapt --chcrt-queries bounds-only --chcrt-hints on --chcrt-leaf-cache on",
        "bench " + scene + all + "--method chcrt-noadapt,chcrt-aggressive --chcrt-queries batched",
        "render " + scene + "--method chcrt --chcrt-queries batched --debug-image overdraw -o batched_overdraw.png",
        // Line Space modes the methods' defaults leave out.
        "bench " + scene + all + "--method bvh+ls --ls-modes primary=exact,shadow=shadow,ao=candidate-exact-start,"
                                 "diffuse=candidate,bounce=exact,faces=both",
        "prepare --scene city:4k --subtree-triangles 500 -o small.chs -q",
        "render --scene small.chs --out-of-core --method chcrt --width 24 --height 16 --spp 1 -q -o ooc.png",
        // Without the scene in core, primary visibility is resolved from the subtrees' hits
        // (outofcore/gbuffer_from_pixel_attributes).
        "render --scene small.chs --out-of-core --load-in-core off --method chcrt --width 24 --height 16 --spp 1 -q "
        "-o ooc_streamed.png",
    };
    for (const char* image : {"overdraw", "subtrees", "batches", "cost"}) {
        commands.push_back("render " + scene + "--method chcrt --debug-image " + image + " -o " + image + ".png");
        commands.push_back("render " + scene + "--method chcrt --chcrt-queries gl --debug-image " + image + " -o gl_" +
                           image + ".png");
    }
    for (const std::string& command : commands) {
        const Result r = run(command, env);
        ASSERT_EQ(r.exitCode, 0) << command << "\n" << r.output;
    }

    // The viewer's and the tests' shaders from the embedded table (their variants take no defines).
    std::set<std::string> compiled;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir_ / "dump")) files.push_back(entry.path());
    for (const fs::path& file : files) {
        std::ifstream in(file);
        std::string first;
        std::getline(in, first);
        compiled.insert(first.substr(3)); // "// <path>"
    }
    // Shaders only the tests and the viewer compile, with the host defines their tests give.
    const std::map<std::string, std::vector<std::vector<ShaderDefine>>> standalone = {
        {"test/define_colour.frag.glsl", {{{"RED", "0.25"}, {"GREEN", "0.5"}}, {{"RED", "0.25"}, {"GREEN", "0.5"}, {"USE_BLUE", ""}}}},
        {"test/intersect_twin.frag.glsl", {{{"TWIN_TEXELS_PER_CASE", "8"}}}},
        {"linespace/shaft_index_twin.frag.glsl", {{}, {{"CHCRT_LS_TWIN_FAST", ""}}}},
        {"linespace/linespace_lookup_twin.frag.glsl", {{{"LS_N", "4"}}}},
    };
    std::vector<std::string> missing;
    for (const EmbeddedShader* s = embeddedShaders(); s->path != nullptr; ++s) {
        const std::string path = s->path, ext = stageExtension(path);
        if (ext.empty() || compiled.count(path) != 0) continue;
        const auto own = standalone.find(path);
        if (own == standalone.end() && path.rfind("viewer/", 0) != 0 && path.rfind("test/", 0) != 0) {
            missing.push_back(path);
            continue;
        }
        const std::vector<std::vector<ShaderDefine>> variants =
            own != standalone.end() ? own->second : std::vector<std::vector<ShaderDefine>>{{}};
        for (size_t k = 0; k < variants.size(); ++k) {
            std::vector<ShaderDefine> defines = variants[k];
            defines.push_back({"CHCRT_TRACE_LOOP_CAP", "1"});
            const fs::path file = dir_ / "dump" /
                                  (fs::path(path).stem().stem().string() + "_standalone" + std::to_string(k) + "." + ext);
            std::ofstream(file) << "// " << path << "\n" << preprocessShader(path, defines).text;
            files.push_back(file);
        }
    }
    EXPECT_TRUE(missing.empty()) << "stage files no command compiled (add a command that does): " << missing.size()
                                 << ", first " << (missing.empty() ? "" : missing.front());

    // Each variant, and each once more with the other loop-cap value.
    std::vector<fs::path> variants;
    for (const fs::path& file : files) {
        std::ifstream in(file);
        const std::string text((std::istreambuf_iterator<char>(in)), {});
        variants.push_back(file);
        for (const auto& [from, to] : {std::pair<std::string, std::string>{"#define CHCRT_TRACE_LOOP_CAP 1\n",
                                                                            "#define CHCRT_TRACE_LOOP_CAP 0\n"},
                                       {"#define CHCRT_TRACE_LOOP_CAP 0\n", "#define CHCRT_TRACE_LOOP_CAP 1\n"}}) {
            const size_t at = text.find(from);
            if (at == std::string::npos) continue;
            std::string flipped = text;
            flipped.replace(at, from.size(), to);
            const fs::path other = file.parent_path() / ("flipped_" + file.filename().string());
            std::ofstream(other) << flipped;
            variants.push_back(other);
        }
    }
    // One glslangValidator process per 64 files (a process per file took 40 s of this test); a refused batch is
    // validated again file by file to name the refused ones.
    constexpr size_t kBatch = 64;
    size_t failures = 0;
    for (size_t first = 0; first < variants.size(); first += kBatch) {
        const std::vector<fs::path> batch(variants.begin() + first,
                                          variants.begin() + std::min(variants.size(), first + kBatch));
        if (validate(glslang, batch).empty()) continue;
        for (const fs::path& variant : batch) {
            const std::string errors = validate(glslang, {variant});
            if (!errors.empty() && ++failures <= 3) {
                std::ifstream source(variant);
                std::string name;
                std::getline(source, name);
                ADD_FAILURE() << "glslangValidator refuses " << variant.filename() << " (" << name << "):\n" << errors;
            }
        }
    }
    const size_t validated = variants.size();
    std::printf("[ glslang  ] %zu stage variants validated from %zu files; %zu stage source files compiled by the "
                "commands; %zu refused\n",
                validated, files.size(), compiled.size(), failures);
    EXPECT_EQ(failures, 0u);
    EXPECT_GT(compiled.size(), 15u); // the commands compiled the passes at all
}

} // namespace
} // namespace chcrt::clitest
