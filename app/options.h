#pragma once
// Command-line options shared by the subcommands (pbrt/Blender style), and their translation into the
// renderer's settings struct (renderer/render/render_settings.h).
#include "renderer/bvh/bvh.h"
#include "renderer/render/render_settings.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace chcrt::app {

struct CommonOptions {
    std::string scene = "city";     // procedural spec or file; default: the embedded city
    std::string cameraPath;         // JSON file, or "near" / "far" for generated scenes; default near / default camera
    std::string camera;             // "gltf:<index or name>" selects a camera stored in a glTF file
    std::string eye, target;        // "x,y,z": an explicit single camera (overrides paths)
    float fovY = 60.0f;
    std::string frames;             // --frames; default depends on the command
    int width = 512;
    int height = 512;
    int spp = -1;                   // -1: the command's default
    std::string effects = "shadow,ao,diffuse";
    std::string primary = "raster"; // --primary raster|traced (RenderSettings::primaryVisibility)
    uint32_t seed = 1;
    float rotation = 36.0f;
    float aoLength = 0.02f;
    float exposure = 1.0f;
    std::string gl = "egl";
    bool glDebug = false;
    std::string statsJson;
    bool quiet = false;
    uint32_t bvhLeafSize = 4;
    uint32_t bvhBins = 16;
    // CHC+RT parameters of the chcrt methods (culling/README.md); negative / empty = the method's default.
    int chcrtThreshold = -1;        // --chcrt-threshold: §7 aggressive visibility threshold in rays
    int chcrtMinTile = -1;          // --chcrt-min-tile: §5.2 minimum tile edge in pixels
    int chcrtHeight = -1;           // --chcrt-height: §5.2 maximum termination-subtree height
    int chcrtMultiQuery = -1;       // --chcrt-multi-query: §5.1 pairs per multi-query (1 = off)
    std::string chcrtTighterBounds; // --chcrt-tighter-bounds on|off (§5.1)
    std::string chcrtLeafCache;     // --chcrt-leaf-cache on|off (§5.2)
    std::string chcrtMergedBatch;   // --chcrt-merged-batch on|off (§5.2 batches as one traversal)
    std::string chcrtRayExtent;     // --chcrt-ray-extent on|off (culling/ray_bounds_grid.h)
    std::string chcrtQueries;       // --chcrt-queries gl|bounds-only (ChcrtOptions::queries)
    int chcrtBoundsCell = -1;       // --chcrt-bounds-cell: ray bounds grid cell edge in pixels
    int chcrtBoundsPieces = -1;     // --chcrt-bounds-pieces: boxes per cell
    // Line Space methods (bvh+ls-exact, bvh+ls; linespace/README.md)
    uint32_t lsN = 6;             // --ls-n: patches per face edge
    uint32_t lsDepth = 9;         // --ls-depth: D
    uint32_t lsT = 8;             // --ls-t: T
    float lsAngle = 30.0f;        // --ls-angle: normal-angle threshold of candidates, degrees
    std::string lsNtree;          // --ls-ntree N:d of method ntree+ls (default 6:3)
    int lsNtreeLevel = -1;        // --ls-ntree-level: level whose occupied shafts terminate (-1 = d-1, >= d exact)
    float lsNtreeNear = 0.0f;     // --ls-ntree-near: nodes this many node edges from the origin count as the start
    std::string lsNtreeStart = "skip"; // --ls-ntree-start skip (SS §4.1) | exact: node a shadow ray starts/ends in
    std::string lsModes;          // --ls-modes type=mode,... on top of the method's defaults
    std::string lsCache = "out/cache/linespace"; // --ls-cache: "" disables caching
    // Out-of-core CHC+RT of a prepared scene (.chs; renderer/outofcore/README.md, docs/outofcore.md).
    bool outOfCore = false;         // --out-of-core: chcrt methods trace through the GPU subtree cache
    int gpuCacheMb = 1024;          // --gpu-cache-mb
    int hostCacheMb = 2048;         // --host-cache-mb
    // --uploads-per-trace: subtrees a trace may upload at most (0 = no limit: complete, exact traces; -1, never
    // given on the command line, = the command's default: 0, the interactive viewer 16 — it streams a cold cache)
    int uploadsPerTrace = -1;
    std::string cachePolicy = "lru"; // --cache-policy round-robin|lru
    std::string loadInCore = "auto"; // --load-in-core auto|on|off: also load an --out-of-core scene in core (references)
};

// Adds the shared options to a subcommand. `withEffects`: the command renders shaded images.
void addCommonOptions(CLI::App& command, CommonOptions& options, bool withEffects);

RenderSettings toRenderSettings(const CommonOptions& options, int defaultSpp);
BvhBuildOptions toBvhOptions(const CommonOptions& options);

// "x,y,z" → vector; throws InputError naming the flag.
glm::vec3 parseVec3(const std::string& text, const char* flag);

} // namespace chcrt::app
