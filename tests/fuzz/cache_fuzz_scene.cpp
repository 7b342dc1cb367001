#include "tests/fuzz/cache_fuzz_scene.h"

#include "renderer/scene/procedural/procedural.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace chcrt::fuzz {

const Bvh& cacheFuzzBvh() {
    static const Bvh bvh = [] {
        ProceduralSpec spec;
        if (!parseProceduralSpec("plane-and-box", spec)) throw std::logic_error("plane-and-box is a generator");
        return buildBvh(generateProceduralScene(spec));
    }();
    return bvh;
}

ls::LineSpaceParams cacheFuzzLineSpaceParams() {
    ls::LineSpaceParams p;
    p.n = 2;
    p.depth = 3;
    p.threads = 1;
    return p;
}

ls::NTreeParams cacheFuzzNTreeParams() {
    ls::NTreeParams p;
    p.n = 2;
    p.depth = 1;
    p.threads = 1;
    return p;
}

std::vector<uint8_t> cacheFileWithPayload(const ls::CacheFileHeader& expected, const uint8_t* payload, size_t size) {
    ls::CacheFileHeader header = expected;
    header.payloadBytes = size;
    header.payloadChecksum = ls::fnv1a64(payload, size);
    std::vector<uint8_t> bytes(sizeof(header) + size);
    std::memcpy(bytes.data(), &header, sizeof(header));
    if (size != 0) std::memcpy(bytes.data() + sizeof(header), payload, size);
    return bytes;
}

ls::CacheFileHeader readCacheHeader(const std::filesystem::path& file) {
    ls::CacheFileHeader header{};
    std::ifstream in(file, std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(&header), sizeof(header))) throw std::runtime_error("cannot read " + file.string());
    return header;
}

} // namespace chcrt::fuzz
