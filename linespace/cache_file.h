#pragma once
// The on-disk cache file format shared by the BVH Line Space cache (linespace_cache.h) and the N-tree cache
// (ntree_cache.h): a fixed 56-byte header (magic, format version, up to five build parameters, input hash,
// payload size and FNV-1a 64 checksum), then the payload. Files are written to a temporary name and renamed
// (atomic on POSIX: readers see the old file or the whole new one). Reading checks everything before the
// payload size byte for byte against the expected header, the size, the checksum and that nothing follows;
// the caller then validates the payload's structure (a checksum only catches accidental damage).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <type_traits>
#include <vector>

namespace chcrt::ls {

uint64_t fnv1a64(const void* bytes, size_t size, uint64_t hash = 0xcbf29ce484222325ull);

struct CacheFileHeader {
    char magic[8];          // identifies the kind of file ("CHCRTLS1", "CHCRTNT1")
    uint32_t version;       // bumped whenever the payload or the build algorithm changes
    uint32_t params[5];     // build parameters, unused ones 0
    uint64_t inputHash;     // of the scene data the structure was built from
    uint64_t payloadBytes;  // filled by writeCacheFile
    uint64_t payloadChecksum;
};
static_assert(sizeof(CacheFileHeader) == 56 && std::is_trivially_copyable_v<CacheFileHeader>);

enum class CacheLoad { Loaded, Missing, Corrupt };

// What loadOrBuild* did (reported on the method's stderr line and in bench JSON).
enum class CacheOutcome { Loaded, Built, RebuiltCorrupt };
const char* toString(CacheOutcome outcome);

// Appends trivially copyable values and length-prefixed arrays of them.
class CacheWriter {
public:
    template <typename T>
    void value(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        append(&v, sizeof(T));
    }
    template <typename T>
    void array(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        value<uint64_t>(v.size());
        append(v.data(), v.size() * sizeof(T));
    }
    std::vector<uint8_t> bytes;

private:
    // resize + memcpy rather than insert(pointer range): GCC 12 reports a false stringop-overflow for the latter.
    void append(const void* data, size_t size) {
        if (size == 0) return;
        const size_t at = bytes.size();
        bytes.resize(at + size);
        std::memcpy(bytes.data() + at, data, size);
    }
};

// Reads what CacheWriter wrote; every call returns false instead of reading past the end.
class CacheReader {
public:
    explicit CacheReader(const std::vector<uint8_t>& b) : bytes_(b) {}
    template <typename T>
    bool value(T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        if (bytes_.size() - position_ < sizeof(T)) return false;
        std::memcpy(&v, bytes_.data() + position_, sizeof(T));
        position_ += sizeof(T);
        return true;
    }
    template <typename T>
    bool array(std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        uint64_t count = 0;
        if (!value(count) || count > (bytes_.size() - position_) / sizeof(T)) return false;
        v.resize(count);
        if (count != 0) { // memcpy to an empty vector's null data() is undefined even for 0 bytes
            std::memcpy(v.data(), bytes_.data() + position_, count * sizeof(T));
        }
        position_ += count * sizeof(T);
        return true;
    }
    bool atEnd() const { return position_ == bytes_.size(); }

private:
    const std::vector<uint8_t>& bytes_;
    size_t position_ = 0;
};

// A header with magic, version, params and hash set, payload fields 0.
CacheFileHeader makeCacheFileHeader(const char (&magic)[9], uint32_t version, std::initializer_list<uint32_t> params,
                                    uint64_t inputHash);

// Writes header (payload size and checksum filled in) + payload atomically. Throws InputError when the
// directory or file cannot be written; `what` names the cache in that message.
void writeCacheFile(const std::filesystem::path& file, CacheFileHeader header, const std::vector<uint8_t>& payload,
                    const char* what);

// Missing: no such file. Corrupt: short header, header other than `expected` (up to the payload size), wrong
// size, checksum or trailing bytes. Loaded: `payload` holds the checksummed payload.
CacheLoad readCacheFile(const std::filesystem::path& file, const CacheFileHeader& expected,
                        std::vector<uint8_t>& payload);

// The protocol both caches follow: `load(T&)` the cache file (returns CacheLoad), else `build()` and `save(const T&)`
// it, reporting which happened (a Missing file means Built, a Corrupt one RebuiltCorrupt).
template <typename T, typename Load, typename Build, typename Save>
T loadOrBuildCached(Load&& load, Build&& build, Save&& save, CacheOutcome* outcome) {
    T value;
    const CacheLoad loaded = load(value);
    CacheOutcome result = CacheOutcome::Loaded;
    if (loaded != CacheLoad::Loaded) {
        result = loaded == CacheLoad::Corrupt ? CacheOutcome::RebuiltCorrupt : CacheOutcome::Built;
        value = build();
        save(value);
    }
    if (outcome != nullptr) *outcome = result;
    return value;
}

} // namespace chcrt::ls
