// The BVH Line Space cache reader: the input is the payload of a cache for the fixed scene (cache_fuzz_scene.h),
// written behind a valid header with its size and checksum, so loadLineSpaceCache's structural validation sees
// every mutation.
#include "linespace/linespace_cache.h"
#include "tests/fuzz/cache_fuzz_scene.h"
#include "tests/fuzz/fuzz_input.h"

namespace {

const chcrt::ls::LineSpaceParams& params() {
    static const chcrt::ls::LineSpaceParams p = chcrt::fuzz::cacheFuzzLineSpaceParams();
    return p;
}

const chcrt::ls::CacheFileHeader& expectedHeader() {
    static const chcrt::ls::CacheFileHeader header = [] {
        const chcrt::Bvh& bvh = chcrt::fuzz::cacheFuzzBvh();
        const auto file = chcrt::fuzz::scratchDirectory() / "valid.lscache";
        chcrt::ls::saveLineSpaceCache(file, chcrt::ls::lineSpaceInputHash(bvh), chcrt::ls::buildLineSpaces(bvh, params()));
        return chcrt::fuzz::readCacheHeader(file);
    }();
    return header;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    const chcrt::Bvh& bvh = chcrt::fuzz::cacheFuzzBvh();
    const std::vector<uint8_t> bytes = chcrt::fuzz::cacheFileWithPayload(expectedHeader(), data, size);
    const auto file = chcrt::fuzz::writeScratchFile(bytes.data(), bytes.size(), ".lscache");
    chcrt::fuzz::expectOnlyInputErrors([&] {
        chcrt::ls::LineSpaces spaces;
        (void)chcrt::ls::loadLineSpaceCache(file, bvh, chcrt::ls::lineSpaceInputHash(bvh), params(), spaces);
    });
    return 0;
}
