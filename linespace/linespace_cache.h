#pragma once
// On-disk cache of built Line Spaces, keyed by a hash of the BVH (its nodes and its triangles with their
// vertices and original ids: everything a Line Space is computed from, so the scene and the BVH build are
// both covered) and the build parameters. Files are checksummed (FNV-1a 64 over the payload), written to a
// temporary file and renamed into place (atomic on POSIX), and fully validated on load: a truncated, corrupt
// or mismatching file is reported and rebuilt, never trusted.
#include "linespace/cache_file.h"
#include "linespace/linespace_build.h"

#include <cstdint>
#include <filesystem>

namespace chcrt::ls {

// FNV-1a 64 over the BVH nodes and triangles.
uint64_t lineSpaceInputHash(const Bvh& bvh);

// <dir>/linespace_<hash>_N<n>_D<d>_T<t>_<binary|candidates>.bin
std::filesystem::path lineSpaceCachePath(const std::filesystem::path& dir, uint64_t inputHash,
                                         const LineSpaceParams& params);

// Loads `file` into `out` when it holds Line Spaces of this BVH (hash) and parameters and passes every check.
CacheLoad loadLineSpaceCache(const std::filesystem::path& file, const Bvh& bvh, uint64_t inputHash,
                             const LineSpaceParams& params, LineSpaces& out);

// Writes atomically (temporary file + rename). Throws InputError when the directory cannot be written.
void saveLineSpaceCache(const std::filesystem::path& file, uint64_t inputHash, const LineSpaces& spaces);

// Loads from `cacheDir` or builds (and saves). An empty cacheDir disables caching (always builds).
LineSpaces loadOrBuildLineSpaces(const Bvh& bvh, const LineSpaceParams& params, const std::filesystem::path& cacheDir,
                                 Progress& progress = nullProgress(), CacheOutcome* outcome = nullptr);

} // namespace chcrt::ls
