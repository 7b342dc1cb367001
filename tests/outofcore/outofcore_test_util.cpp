#include "tests/outofcore/outofcore_test_util.h"

#include <cstring>

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
                                      uint32_t subtreeTriangles, uint64_t memoryBytes, bool compact) {
    outofcore::PrepareOptions options;
    options.compact = compact;
    options.subtreeTriangles = subtreeTriangles;
    options.memoryBytes = memoryBytes;
    return outofcore::prepareScene(scene, file, options);
}

bool sameContents(const outofcore::SubtreeData& a, const outofcore::SubtreeData& b) {
    const auto same = [](const auto& x, const auto& y) {
        return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
    };
    if (a.compact() != b.compact() || a.triangleCount() != b.triangleCount()) return false;
    if (a.compact()) return same(a.compactNodes, b.compactNodes) && same(a.compactTriangles, b.compactTriangles) &&
                            same(a.vertices, b.vertices);
    return same(a.nodes, b.nodes) && same(a.triangles, b.triangles);
}

} // namespace chcrt::test
