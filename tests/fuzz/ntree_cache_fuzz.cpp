// The N-tree cache reader: the input is the payload of a cache for the fixed scene (cache_fuzz_scene.h),
// written behind a valid header with its size and checksum, so loadNTreeCache's structural validation sees
// every mutation.
#include "linespace/ntree_cache.h"
#include "tests/fuzz/cache_fuzz_scene.h"
#include "tests/fuzz/fuzz_input.h"

namespace {

const chcrt::ls::NTreeParams& params() {
    static const chcrt::ls::NTreeParams p = chcrt::fuzz::cacheFuzzNTreeParams();
    return p;
}

const chcrt::ls::CacheFileHeader& expectedHeader() {
    static const chcrt::ls::CacheFileHeader header = [] {
        const chcrt::Bvh& bvh = chcrt::fuzz::cacheFuzzBvh();
        const auto file = chcrt::fuzz::scratchDirectory() / "valid.ntcache";
        chcrt::ls::saveNTreeCache(file, chcrt::ls::nTreeInputHash(bvh), chcrt::ls::buildNTree(bvh, params()));
        return chcrt::fuzz::readCacheHeader(file);
    }();
    return header;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    const chcrt::Bvh& bvh = chcrt::fuzz::cacheFuzzBvh();
    const std::vector<uint8_t> bytes = chcrt::fuzz::cacheFileWithPayload(expectedHeader(), data, size);
    const auto file = chcrt::fuzz::writeScratchFile(bytes.data(), bytes.size(), ".ntcache");
    chcrt::fuzz::expectOnlyInputErrors([&] {
        chcrt::ls::NTree tree;
        (void)chcrt::ls::loadNTreeCache(file, bvh, chcrt::ls::nTreeInputHash(bvh), params(), tree);
    });
    return 0;
}
