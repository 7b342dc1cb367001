#include "tests/outofcore/outofcore_test_util.h"

#include <atomic>
#include <fstream>
#include <unistd.h>

namespace chcrt::test {

ScratchDir::ScratchDir() {
    static std::atomic<int> counter{0};
    dir_ = std::filesystem::temp_directory_path() /
           ("chcrt_outofcore_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::create_directories(dir_);
}

ScratchDir::~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
}

std::vector<char> readBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

void writeBytes(const std::filesystem::path& file, const std::vector<char>& bytes) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

outofcore::PrepareReport prepareSmall(const std::string& scene, const std::filesystem::path& file,
                                      uint32_t subtreeTriangles, uint64_t memoryBytes) {
    outofcore::PrepareOptions options;
    options.subtreeTriangles = subtreeTriangles;
    options.memoryBytes = memoryBytes;
    return outofcore::prepareScene(scene, file, options);
}

} // namespace chcrt::test
