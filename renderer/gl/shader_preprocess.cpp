// Shader sources (embedded or from CHCRT_SHADER_DIR), the #include paster and the compile-log mapper of
// shader.h. Pure CPU code: no GL calls, so it is testable without a context.
#include "renderer/core/error.h"
#include "renderer/gl/shader.h"
#include "shaders/embedded_shaders.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string_view>
#include <unordered_map>

namespace chcrt {
namespace {

// Lexically normalised path relative to shaders/ ("a/./b/../c" -> "a/c"); empty when it leaves the root.
std::string normalizePath(const std::string& path) {
    std::vector<std::string> parts;
    std::istringstream stream(path);
    std::string part;
    while (std::getline(stream, part, '/')) {
        if (part.empty() || part == ".") {
            continue;
        }
        if (part == "..") {
            if (parts.empty()) {
                return "";
            }
            parts.pop_back();
            continue;
        }
        parts.push_back(part);
    }
    std::string result;
    for (const std::string& p : parts) {
        result += (result.empty() ? "" : "/") + p;
    }
    return result;
}

// The directory the shader files come from, for error messages.
std::string sourceOrigin() {
    const char* dir = std::getenv("CHCRT_SHADER_DIR");
    return dir != nullptr && *dir != '\0' ? std::string("CHCRT_SHADER_DIR=") + dir
                                          : "the embedded shader table (set CHCRT_SHADER_DIR to load from disk)";
}

// Text of a shader file (path relative to shaders/, normalised), or nullopt. CHCRT_SHADER_DIR is read on every
// call so the viewer can reload from disk, and tests can point it at a scratch directory.
std::optional<std::string> readShaderSource(const std::string& path) {
    if (path.empty()) {
        return std::nullopt;
    }
    const char* dir = std::getenv("CHCRT_SHADER_DIR");
    if (dir != nullptr && *dir != '\0') {
        std::ifstream file(std::string(dir) + "/" + path, std::ios::binary);
        if (!file) {
            return std::nullopt;
        }
        std::ostringstream text;
        text << file.rdbuf();
        return text.str();
    }
    static const std::unordered_map<std::string, const char*> table = [] {
        std::unordered_map<std::string, const char*> map;
        for (const EmbeddedShader* s = embeddedShaders(); s->path != nullptr; ++s) {
            map.emplace(s->path, s->text);
        }
        return map;
    }();
    auto it = table.find(path);
    return it != table.end() ? std::optional<std::string>(it->second) : std::nullopt;
}

std::string_view trimLeft(std::string_view s) {
    size_t i = 0;
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) {
        ++i;
    }
    return s.substr(i);
}

// "#  include ..." -> "include" (empty when the line is not a directive), rest of the line in `rest`.
std::string_view directiveName(std::string_view line, std::string_view& rest) {
    line = trimLeft(line);
    if (line.empty() || line[0] != '#') {
        return {};
    }
    line = trimLeft(line.substr(1));
    size_t end = 0;
    while (end < line.size() && (std::isalnum(static_cast<unsigned char>(line[end])) || line[end] == '_')) {
        ++end;
    }
    rest = trimLeft(line.substr(end));
    return line.substr(0, end);
}

// Updates the block-comment state across one line (GLSL has no string literals outside #include, so comment
// markers cannot hide inside strings).
bool blockCommentAfter(std::string_view line, bool inComment) {
    for (size_t i = 0; i < line.size(); ++i) {
        if (inComment) {
            if (i + 1 < line.size() && line[i] == '*' && line[i + 1] == '/') {
                inComment = false;
                ++i;
            }
        } else if (i + 1 < line.size() && line[i] == '/' && line[i + 1] == '/') {
            break;
        } else if (i + 1 < line.size() && line[i] == '/' && line[i + 1] == '*') {
            inComment = true;
            ++i;
        }
    }
    return inComment;
}

std::vector<std::string_view> splitLines(const std::string& text) {
    std::vector<std::string_view> lines;
    std::string_view all(text);
    size_t pos = 0;
    while (pos < all.size()) {
        size_t end = all.find('\n', pos);
        if (end == std::string_view::npos) {
            end = all.size();
        }
        std::string_view line = all.substr(pos, end - pos);
        if (!line.empty() && line.back() == '\r') {
            line.remove_suffix(1);
        }
        lines.push_back(line);
        pos = end + 1;
    }
    return lines;
}

class Preprocessor {
public:
    explicit Preprocessor(PreprocessedShader& result) : result_(result) {}

    void run(const std::string& rootPath, const std::vector<ShaderDefine>& defines) {
        const std::string path = normalizePath(rootPath);
        std::optional<std::string> text = readShaderSource(path);
        if (!text) {
            throw GlError("shader file '" + rootPath + "' not found in " + sourceOrigin());
        }
        // Step 1: #version must stay the first directive, so it is emitted before the defines; its own line is
        // blanked below, which keeps the root file's line numbers intact.
        std::vector<std::string_view> lines = splitLines(*text);
        versionLine_ = -1;
        for (size_t i = 0; i < lines.size(); ++i) {
            std::string_view rest;
            if (directiveName(lines[i], rest) == "version") {
                versionLine_ = static_cast<int>(i);
                result_.text.append(lines[i]).append("\n");
                break;
            }
        }
        // Step 2: the variant's defines. Those whose value is a quoted path name a file for `#include NAME` and
        // are resolved here, not passed on (GLSL has no string literals).
        for (const ShaderDefine& define : defines) {
            if (!define.value.empty() && define.value.front() == '"') {
                includeNames_[define.name] = unquote(define.value, "define " + define.name);
                continue;
            }
            result_.text += "#define " + define.name + (define.value.empty() ? "" : " " + define.value) + "\n";
        }
        // Step 3: the root and everything it includes, with #line directives.
        appendFile(path, *text, true);
    }

private:
    static std::string unquote(std::string_view text, const std::string& where) {
        const size_t close = text.size() > 1 ? text.find('"', 1) : std::string_view::npos;
        if (text.empty() || text[0] != '"' || close == std::string_view::npos) {
            throw GlError("malformed quoted path at " + where);
        }
        return std::string(text.substr(1, close - 1));
    }

    static bool isIdentifierStart(std::string_view text) {
        return !text.empty() && (std::isalpha(static_cast<unsigned char>(text[0])) || text[0] == '_');
    }

    static std::string_view identifier(std::string_view text) {
        size_t end = 0;
        while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_')) {
            ++end;
        }
        return text.substr(0, end);
    }

    int fileIndex(const std::string& path) {
        auto it = std::find(result_.files.begin(), result_.files.end(), path);
        if (it != result_.files.end()) {
            return static_cast<int>(it - result_.files.begin());
        }
        result_.files.push_back(path);
        return static_cast<int>(result_.files.size() - 1);
    }

    // `#include "name"` resolves against shaders/ first, then the including file's directory.
    std::string resolveInclude(const std::string& name, const std::string& includer, std::string& text) {
        std::string candidate = normalizePath(name);
        if (std::optional<std::string> found = readShaderSource(candidate)) {
            text = std::move(*found);
            return candidate;
        }
        const size_t slash = includer.rfind('/');
        if (slash != std::string::npos) {
            candidate = normalizePath(includer.substr(0, slash + 1) + name);
            if (std::optional<std::string> found = readShaderSource(candidate)) {
                text = std::move(*found);
                return candidate;
            }
        }
        return "";
    }

    void emitLine(int line, int index) {
        result_.text += "#line " + std::to_string(line) + " " + std::to_string(index) + "\n";
    }

    void appendFile(const std::string& path, const std::string& text, bool isRoot) {
        const int index = fileIndex(path);
        stack_.push_back(path);
        // GLSL >= 3.30: "#line L S" makes the *next* line number L of source string S.
        emitLine(1, index);
        std::vector<std::string_view> lines = splitLines(text);
        bool inComment = false;
        bool pastedInclude = false;
        for (size_t i = 0; i < lines.size(); ++i) {
            const std::string_view line = lines[i];
            const int lineNumber = static_cast<int>(i) + 1;
            const bool commentedOut = inComment;
            inComment = blockCommentAfter(line, inComment);
            std::string_view rest;
            const std::string_view directive = commentedOut ? std::string_view() : directiveName(line, rest);
            if (isRoot && static_cast<int>(i) == versionLine_) {
                result_.text += "\n";
            } else if (directive == "include" && !rest.empty() && (rest[0] == '"' || isIdentifierStart(rest))) {
                const std::string where = path + ":" + std::to_string(lineNumber);
                const std::string name = rest[0] == '"' ? unquote(rest, "#include at " + where) : includeName(rest, where);
                pasteInclude(name, path, lineNumber);
                emitLine(lineNumber + 1, index);
                pastedInclude = true;
            } else if (directive == "define" && isIdentifierStart(rest) &&
                       trimLeft(rest.substr(identifier(rest).size())).substr(0, 1) == "\"") {
                // `#define NAME "path"`: the file `#include NAME` pastes unless the host defines NAME (the usual
                // `#ifndef NAME` guard around it therefore reads as it behaves).
                const std::string name(identifier(rest));
                const std::string value = unquote(trimLeft(rest.substr(name.size())), path + ":" + std::to_string(lineNumber));
                includeDefaults_.try_emplace(name, value);
                result_.text += "\n";
            } else if (directive == "pragma" && rest.substr(0, 4) == "once") {
                pragmaOnce_.push_back(path);
                result_.text += "\n";
            } else {
                result_.text.append(line).append("\n");
                // A pasted file inside a conditional the compiler skips also skips the #line that restores this
                // file's numbering; re-sync wherever skipping can end.
                if (pastedInclude && (directive == "endif" || directive == "else" || directive == "elif")) {
                    emitLine(lineNumber + 1, index);
                }
            }
        }
        stack_.pop_back();
    }

    // Includes are pasted every time (the shared headers' #ifndef guards then do their job in the compiler,
    // and shared_begin.h/shared_end.h must be pasted at every use); only a file that includes itself through
    // the include chain is an error. Files with `#pragma once` are pasted once.
    void pasteInclude(const std::string& name, const std::string& includer, int lineNumber) {
        std::string text;
        const std::string path = resolveInclude(name, includer, text);
        const std::string where = includer + ":" + std::to_string(lineNumber);
        if (path.empty()) {
            throw GlError("shader include \"" + name + "\" (from " + where + ") not found in " + sourceOrigin());
        }
        if (std::find(pragmaOnce_.begin(), pragmaOnce_.end(), path) != pragmaOnce_.end()) {
            return;
        }
        if (std::find(stack_.begin(), stack_.end(), path) != stack_.end()) {
            std::string chain;
            for (const std::string& file : stack_) {
                chain += file + " -> ";
            }
            throw GlError("shader include cycle: " + chain + path + " (at " + where + ")");
        }
        appendFile(path, text, false);
    }

    // `#include NAME`: the path the host's define NAME gives, else the file's own `#define NAME "path"`.
    std::string includeName(std::string_view rest, const std::string& where) const {
        const std::string name(identifier(rest));
        if (auto it = includeNames_.find(name); it != includeNames_.end()) return it->second;
        if (auto it = includeDefaults_.find(name); it != includeDefaults_.end()) return it->second;
        throw GlError("#include " + name + " at " + where + ": " + name + " names no file (define it as \"path\")");
    }

    PreprocessedShader& result_;
    std::unordered_map<std::string, std::string> includeNames_;    // host defines with a quoted path
    std::unordered_map<std::string, std::string> includeDefaults_; // #define NAME "path" in the files
    std::vector<std::string> stack_;
    std::vector<std::string> pragmaOnce_;
    int versionLine_ = -1;
};

} // namespace

PreprocessedShader preprocessShader(const std::string& path, const std::vector<ShaderDefine>& defines) {
    PreprocessedShader result;
    Preprocessor(result).run(path, defines);
    return result;
}

std::string mapShaderLog(const std::string& log, const std::vector<std::string>& files) {
    // Mesa "0:12(5): error: ...", NVIDIA "0(12) : error C0000: ...", AMD/glslang "ERROR: 0:12: ...".
    static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\)(.*)$)");
    static const std::regex nvidia(R"(^(\d+)\((\d+)\)\s*:(.*)$)");
    static const std::regex glslang(R"(^(ERROR|WARNING): (\d+):(\d+):(.*)$)");
    auto fileName = [&](const std::string& number) -> std::string {
        const unsigned long index = std::stoul(number);
        return index < files.size() ? files[index] : number;
    };
    std::string mapped;
    std::istringstream stream(log);
    std::string line;
    std::smatch m;
    while (std::getline(stream, line)) {
        if (std::regex_match(line, m, mesa)) {
            line = fileName(m[1]) + ":" + m[2].str() + "(" + m[3].str() + ")" + m[4].str();
        } else if (std::regex_match(line, m, nvidia)) {
            line = fileName(m[1]) + ":" + m[2].str() + ":" + m[3].str();
        } else if (std::regex_match(line, m, glslang)) {
            line = m[1].str() + ": " + fileName(m[2]) + ":" + m[3].str() + ":" + m[4].str();
        }
        mapped += line + "\n";
    }
    return mapped;
}

} // namespace chcrt
