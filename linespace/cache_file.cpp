#include "linespace/cache_file.h"

#include "renderer/core/error.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

namespace chcrt::ls {

uint64_t fnv1a64(const void* bytes, size_t size, uint64_t hash) {
    const auto* p = static_cast<const uint8_t*>(bytes);
    for (size_t i = 0; i < size; ++i) {
        hash = (hash ^ p[i]) * 0x100000001b3ull;
    }
    return hash;
}

CacheFileHeader makeCacheFileHeader(const char (&magic)[9], uint32_t version, std::initializer_list<uint32_t> params,
                                    uint64_t inputHash) {
    CacheFileHeader h{};
    std::memcpy(h.magic, magic, sizeof(h.magic));
    h.version = version;
    std::copy_n(params.begin(), std::min<size_t>(params.size(), 5), h.params);
    h.inputHash = inputHash;
    return h;
}

const char* toString(CacheOutcome outcome) {
    switch (outcome) {
    case CacheOutcome::Loaded:
        return "loaded from cache";
    case CacheOutcome::Built:
        return "built";
    case CacheOutcome::RebuiltCorrupt:
        return "rebuilt (cache file was corrupt or stale)";
    }
    return "?";
}

void writeCacheFile(const std::filesystem::path& file, CacheFileHeader header, const std::vector<uint8_t>& payload,
                    const char* what) {
    header.payloadBytes = payload.size();
    header.payloadChecksum = fnv1a64(payload.data(), payload.size());
    std::error_code ec;
    if (!file.parent_path().empty()) {
        std::filesystem::create_directories(file.parent_path(), ec);
    }
    // Unique temporary name in the same directory, then rename: readers see the old file or the whole new one.
    std::filesystem::path temporary = file;
    temporary += ".tmp." + std::to_string(::getpid());
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(&header), sizeof(header));
        out.write(reinterpret_cast<const char*>(payload.data()), std::streamsize(payload.size()));
        out.flush();
        if (!out) {
            std::filesystem::remove(temporary, ec);
            throw InputError(std::string("cannot write ") + what + " " + temporary.string());
        }
    }
    std::filesystem::rename(temporary, file, ec);
    if (ec) {
        std::filesystem::remove(temporary, ec);
        throw InputError(std::string("cannot move ") + what + " into place: " + file.string());
    }
}

CacheLoad readCacheFile(const std::filesystem::path& file, const CacheFileHeader& expected,
                        std::vector<uint8_t>& payload) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        return CacheLoad::Missing;
    }
    CacheFileHeader header{};
    if (!in.read(reinterpret_cast<char*>(&header), sizeof(header))) {
        return CacheLoad::Corrupt;
    }
    // Everything before the payload size must match byte for byte (magic, version, parameters, hash).
    if (std::memcmp(&header, &expected, offsetof(CacheFileHeader, payloadBytes)) != 0 ||
        header.payloadBytes > (uint64_t(1) << 40)) {
        return CacheLoad::Corrupt;
    }
    // Compare the size with the file before allocating: a damaged size field must not allocate a terabyte.
    std::error_code ec;
    const uintmax_t fileSize = std::filesystem::file_size(file, ec);
    if (ec || fileSize != sizeof(header) + header.payloadBytes) {
        return CacheLoad::Corrupt;
    }
    payload.assign(header.payloadBytes, 0);
    if (!in.read(reinterpret_cast<char*>(payload.data()), std::streamsize(payload.size())) || in.peek() != EOF ||
        fnv1a64(payload.data(), payload.size()) != header.payloadChecksum) {
        return CacheLoad::Corrupt;
    }
    return CacheLoad::Loaded;
}

} // namespace chcrt::ls
