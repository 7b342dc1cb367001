#pragma once
// Scratch files and small helpers shared by the out-of-core tests.
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

// Prepares `scene` into `file` with small subtrees (so even small scenes have many) and a given budget.
outofcore::PrepareReport prepareSmall(const std::string& scene, const std::filesystem::path& file,
                                      uint32_t subtreeTriangles = 1000, uint64_t memoryBytes = 256ull << 20);

} // namespace chcrt::test
