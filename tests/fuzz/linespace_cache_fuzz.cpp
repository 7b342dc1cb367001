// The BVH Line Space cache reader: the input is the payload of a cache for the fixed scene (cache_fuzz_scene.h),
// written behind a valid header with its size and checksum, so loadLineSpaceCache's structural validation sees
// every mutation.
#include "linespace/linespace_cache.h"
#include "tests/fuzz/cache_fuzz_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace chcrt;
    static const ls::LineSpaceParams params = fuzz::cacheFuzzLineSpaceParams();
    const Bvh& bvh = fuzz::cacheFuzzBvh();
    return fuzz::fuzzCacheReader(
        data, size, ".lscache",
        [&](const std::filesystem::path& file) {
            ls::saveLineSpaceCache(file, ls::lineSpaceInputHash(bvh), ls::buildLineSpaces(bvh, params));
        },
        [&](const std::filesystem::path& file) {
            ls::LineSpaces spaces;
            (void)ls::loadLineSpaceCache(file, bvh, ls::lineSpaceInputHash(bvh), params, spaces);
        });
}
