#pragma once
// The fixture of the CLI tests: runs build/bin/chcrt (path injected by CMake as CHCRT_BINARY) in a temporary
// directory of its own and reads what it left there.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace chcrt::clitest {

namespace fs = std::filesystem;

struct Result {
    int exitCode = -1;
    std::string output; // stdout and stderr
};

// Runs build/bin/chcrt with `arguments` in `dir`; `environment`: assignments put before the binary ("PATH=/x").
inline Result runChcrt(const fs::path& dir, const std::string& arguments, const std::string& environment = "") {
    const std::string command = "cd '" + dir.string() + "' && " + (environment.empty() ? "" : "env " + environment + " ") +
                                "'" CHCRT_BINARY "' " + arguments + " 2>&1";
    Result result;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    while (size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) result.output.append(buffer.data(), n);
    const int status = ::pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

class CliTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("chcrt_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
                std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    Result run(const std::string& arguments, const std::string& environment = "") const {
        return runChcrt(dir_, arguments, environment);
    }

    void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
    bool exists(const std::string& name) const { return fs::exists(dir_ / name); }
    // No stray temp files either (atomic writes clean up after themselves).
    size_t fileCount() const { return size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator())); }
    nlohmann::json readJson(const std::string& name) const {
        std::ifstream in(dir_ / name);
        return nlohmann::json::parse(in);
    }
    std::string readFile(const std::string& name) const {
        std::ifstream in(dir_ / name, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }

    fs::path dir_;
};

// `output` without the line every GL command prints when it renders on a software renderer (llvmpipe: "warning:
// OpenGL renders on the software renderer ...", app/session.cpp), for tests that want no other warning.
inline std::string withoutSoftwareRendererWarning(const std::string& output) {
    const std::string marker = "warning: OpenGL renders on the software renderer";
    std::string kept;
    size_t start = 0;
    while (start < output.size()) {
        size_t end = output.find('\n', start);
        end = end == std::string::npos ? output.size() : end + 1;
        if (output.compare(start, marker.size(), marker) != 0) kept.append(output, start, end - start);
        start = end;
    }
    return kept;
}

// Small frames for tests that only need the command to run.
constexpr const char* kSmall = "--width 48 --height 32 --spp 1 -q";

} // namespace chcrt::clitest
