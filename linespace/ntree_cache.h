#pragma once
// On-disk cache of built N-trees (method ntree+ls; build 5-200 s on the scenes we have), in the format of
// cache_file.h. Key: a hash of the scene's triangles in GPU order (vertices, original ids) and the root bounds
// (everything buildNTree reads), the N-tree parameters (N, d) and the format version; the same key is stored
// in the header and compared byte for byte. Payload checksummed, written atomically. Loading also validates
// the structure against the scene: the root, every subdivided node's N^3 children (positions, sizes, levels,
// the breadth-first child and Line Space numbering of buildNTree), triangle ranges and ids, the bitset sizes
// and no bits past the last shaft. Anything wrong -> reported as corrupt and rebuilt, never trusted.
#include "linespace/cache_file.h"
#include "linespace/ntree.h"

#include <cstdint>
#include <filesystem>

namespace chcrt::ls {

// FNV-1a 64 over the triangles and the root bounds.
uint64_t nTreeInputHash(const Bvh& bvh);

// <dir>/ntree_<hash>_N<n>_d<depth>.bin
std::filesystem::path nTreeCachePath(const std::filesystem::path& dir, uint64_t inputHash, const NTreeParams& params);

// Loads `file` into `out` when it holds the N-tree of this scene (hash) and parameters and passes every check.
CacheLoad loadNTreeCache(const std::filesystem::path& file, const Bvh& bvh, uint64_t inputHash,
                         const NTreeParams& params, NTree& out);

// Writes atomically (temporary file + rename). Throws InputError when the directory cannot be written.
void saveNTreeCache(const std::filesystem::path& file, uint64_t inputHash, const NTree& tree);

// Loads from `cacheDir` or builds (and saves). An empty cacheDir disables caching (always builds).
NTree loadOrBuildNTree(const Bvh& bvh, const NTreeParams& params, const std::filesystem::path& cacheDir,
                       Progress& progress = nullProgress(), CacheOutcome* outcome = nullptr);

} // namespace chcrt::ls
