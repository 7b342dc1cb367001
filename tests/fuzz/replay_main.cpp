// A main for the harnesses when they are built without libFuzzer (the GCC sanitizer build): runs every file given
// on the command line, or found under a directory given there, through LLVMFuzzerTestOneInput once, so the seed
// corpora and the regression inputs run under ctest. A crash or sanitizer report ends the process; an escaping
// exception other than InputError is reported with the file's name and fails the run.
#include "tests/fuzz/fuzz_input.h"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

int main(int argc, char** argv) {
    std::vector<std::filesystem::path> files;
    for (int i = 1; i < argc; ++i) {
        const std::filesystem::path arg = argv[i];
        if (std::filesystem::is_directory(arg)) {
            for (const auto& entry : std::filesystem::recursive_directory_iterator(arg)) {
                if (entry.is_regular_file()) files.push_back(entry.path());
            }
        } else {
            files.push_back(arg);
        }
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) {
        std::fprintf(stderr, "no inputs (give files or directories)\n");
        return 1;
    }
    for (const auto& file : files) {
        std::ifstream in(file, std::ios::binary);
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        try {
            LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: uncaught exception: %s\n", file.c_str(), e.what());
            return 1;
        }
    }
    std::printf("%zu input(s) ran cleanly\n", files.size());
    return 0;
}
