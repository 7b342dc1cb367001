// The N-tree cache reader: the input is the payload of a cache for the fixed scene (cache_fuzz_scene.h),
// written behind a valid header with its size and checksum, so loadNTreeCache's structural validation sees
// every mutation.
#include "linespace/ntree_cache.h"
#include "tests/fuzz/cache_fuzz_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace chcrt;
    static const ls::NTreeParams params = fuzz::cacheFuzzNTreeParams();
    const Bvh& bvh = fuzz::cacheFuzzBvh();
    return fuzz::fuzzCacheReader(
        data, size, ".ntcache",
        [&](const std::filesystem::path& file) {
            ls::saveNTreeCache(file, ls::nTreeInputHash(bvh), ls::buildNTree(bvh, params));
        },
        [&](const std::filesystem::path& file) {
            ls::NTree tree;
            (void)ls::loadNTreeCache(file, bvh, ls::nTreeInputHash(bvh), params, tree);
        });
}
