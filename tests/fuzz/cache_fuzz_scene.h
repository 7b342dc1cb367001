#pragma once
// The scene both cache harnesses validate their input against: the Line Space and N-tree cache readers check a
// payload's structure against the BVH it was built for, so the harnesses (and the seeds, tests/fuzz/make_seeds.cpp)
// use one small fixed scene, and the file header a valid cache of it has.
#include "linespace/cache_file.h"
#include "linespace/linespace_build.h"
#include "linespace/ntree.h"
#include "renderer/bvh/bvh.h"
#include "tests/fuzz/fuzz_input.h"

#include <filesystem>
#include <string>
#include <vector>

namespace chcrt::fuzz {

// The BVH of the "plane-and-box" generator scene.
const Bvh& cacheFuzzBvh();

// Small build parameters (N = 2, shallow), so a valid payload, and with it each seed, is a few KB.
ls::LineSpaceParams cacheFuzzLineSpaceParams();
ls::NTreeParams cacheFuzzNTreeParams();

// A whole cache file: `expected` (the header a valid cache has) with the payload's size and checksum, then the
// payload, so the reader gets past the checksum to the payload's structure.
std::vector<uint8_t> cacheFileWithPayload(const ls::CacheFileHeader& expected, const uint8_t* payload, size_t size);

// The header at the start of a cache file (from a cache written once by the harness).
ls::CacheFileHeader readCacheHeader(const std::filesystem::path& file);

// One input of a cache reader's harness: `data` is the payload of a cache file with extension `extension`
// (".lscache"), written behind the header of a valid cache of the fixed scene — which `saveValid(path)` writes once —
// and read back by `load(path)`; only input errors are expected.
template <typename SaveValid, typename Load>
int fuzzCacheReader(const uint8_t* data, size_t size, const std::string& extension, SaveValid saveValid, Load load) {
    const CpuTimeLimit limit;
    static const ls::CacheFileHeader expected = [&] {
        const std::filesystem::path file = scratchDirectory() / ("valid" + extension);
        saveValid(file);
        return readCacheHeader(file);
    }();
    const std::vector<uint8_t> bytes = cacheFileWithPayload(expected, data, size);
    const std::filesystem::path file = writeScratchFile(bytes.data(), bytes.size(), extension);
    expectOnlyInputErrors([&] { load(file); });
    return 0;
}

} // namespace chcrt::fuzz
