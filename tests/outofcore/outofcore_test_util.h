#pragma once
// Scratch files and small helpers shared by the out-of-core tests.
#include "renderer/outofcore/chs_file.h"
#include "renderer/outofcore/prepare.h"

#include <filesystem>
#include <string>
#include <vector>

namespace chcrt::test {

// A fresh directory under the system temp directory, removed on destruction.
class ScratchDir {
public:
    ScratchDir();
    ~ScratchDir();
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    std::filesystem::path file(const std::string& name) const { return dir_ / name; }

private:
    std::filesystem::path dir_;
};

std::vector<char> readBytes(const std::filesystem::path& file);
void writeBytes(const std::filesystem::path& file, const std::vector<char>& bytes);

// Prepares `scene` into `file` with small subtrees (so even small scenes have many) and a given budget, in the
// compact layout (the default of `chcrt prepare`) or the full one.
outofcore::PrepareReport prepareSmall(const std::string& scene, const std::filesystem::path& file,
                                      uint32_t subtreeTriangles = 1000, uint64_t memoryBytes = 256ull << 20,
                                      bool compact = true);
// Two reads hold the same GPU payload (the layout's nodes and triangles, and a compact file's vertices).
bool sameContents(const outofcore::SubtreeData& a, const outofcore::SubtreeData& b);

} // namespace chcrt::test
