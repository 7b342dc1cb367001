#include "app/options.h"

#include "renderer/core/error.h"

#include <cmath>
#include <sstream>

namespace chcrt::app {

void addCommonOptions(CLI::App& c, CommonOptions& o, bool withEffects) {
    c.add_option("--scene", o.scene,
                 "Scene: a .gltf/.glb/.ply/.obj file or a generator spec (city, interior, plant, plane-and-box, "
                 "closed-box, one-triangle; e.g. city:2m:seed=3)")
        ->capture_default_str();
    c.add_option("--camera-path", o.cameraPath,
                 "Walkthrough JSON file, or near/far for a generated scene's street-level/bird's-eye path "
                 "(default: near for generated scenes, the default camera otherwise)");
    c.add_option("--camera", o.camera, "A camera stored in a glTF file: gltf:<index or name>");
    c.add_option("--eye", o.eye, "Explicit camera position x,y,z (with --target; overrides paths)");
    c.add_option("--target", o.target, "Explicit camera target x,y,z");
    c.add_option("--fov", o.fovY, "Vertical field of view in degrees for --eye/--target")->capture_default_str();
    c.add_option("--frames", o.frames, "Frames of the path: all, all:10 (every 10th), 7, 1-100, 1-100:10, 3,5-9, spread:5 (0-based)");
    c.add_option("--width", o.width, "Image width in pixels")->capture_default_str();
    c.add_option("--height", o.height, "Image height in pixels")->capture_default_str();
    c.add_option("--seed", o.seed, "Seed of the per-pixel sample perturbation")->capture_default_str();
    c.add_option("--rotation", o.rotation,
                 "Per-pixel random rotation of the shared sample in degrees (0, 18, 36, 360 = full)")
        ->capture_default_str();
    c.add_option("--ao-length", o.aoLength, "AO ray length as a fraction of the scene diagonal")->capture_default_str();
    c.add_option("--spp", o.spp, "Samples per pixel per effect (= ray passes)");
    c.add_option("--primary", o.primary,
                 "Primary visibility: raster (rasterised G-buffer) or traced (primary rays traced with the "
                 "method's tracer, resolved into the G-buffer)")
        ->capture_default_str();
    if (withEffects) {
        c.add_option("--effects", o.effects, "Secondary effects: any of shadow,ao,diffuse, or all / none")
            ->capture_default_str();
        c.add_option("--exposure", o.exposure, "Exposure before tone mapping")->capture_default_str();
    }
    c.add_option("--gl", o.gl, "OpenGL context: egl (headless, default) or osmesa")->capture_default_str();
    c.add_flag("--gl-debug", o.glDebug, "Print KHR_debug messages from the driver");
    c.add_option("--stats-json", o.statsJson, "Write per-frame statistics as JSON to this file");
    c.add_option("--chcrt-threshold", o.chcrtThreshold,
                 "CHC+RT: a pair is visible only when more rays pass its query (0 = exact; chcrt-aggressive: 20)");
    c.add_option("--chcrt-min-tile", o.chcrtMinTile, "CHC+RT: minimum screen tile edge in pixels (default 64)");
    c.add_option("--chcrt-height", o.chcrtHeight, "CHC+RT: maximum termination-subtree height (default 24)");
    c.add_option("--chcrt-multi-query", o.chcrtMultiQuery,
                 "CHC+RT: previously invisible pairs per multi-query (default 4, 1 = off)");
    c.add_option("--chcrt-tighter-bounds", o.chcrtTighterBounds, "CHC+RT: query the children's boxes (on|off, default on)");
    c.add_option("--chcrt-leaf-cache", o.chcrtLeafCache, "CHC+RT: 2-entry leaf cache in subtree traversal (on|off, default off)");
    c.add_option("--chcrt-merged-batch", o.chcrtMergedBatch,
                 "CHC+RT: traverse a batch's subtrees as one traversal instead of one after another (on|off, default on)");
    c.add_option("--chcrt-ray-extent", o.chcrtRayExtent,
                 "CHC+RT: skip pairs out of reach of their tile's bounded rays (on|off, default on)");
    c.add_option("--chcrt-queries", o.chcrtQueries,
                 "CHC+RT: how query pairs are decided: gl (GL occlusion queries, per-tile subtree draws; default) or "
                 "bounds-only (the ray bounds grid decides every pair; cell lists, one draw per round)");
    c.add_option("--chcrt-bounds-cell", o.chcrtBoundsCell, "CHC+RT: ray bounds grid cell edge in pixels (default 8)");
    c.add_option("--chcrt-bounds-pieces", o.chcrtBoundsPieces, "CHC+RT: ray bounds boxes per cell (default 4)");
    c.add_flag("-q,--quiet", o.quiet, "No progress bars");
    c.add_option("--bvh-leaf-size", o.bvhLeafSize, "Maximum triangles per BVH leaf")->capture_default_str();
    c.add_option("--bvh-bins", o.bvhBins, "SAH bins per axis")->capture_default_str();
    c.add_option("--ls-n", o.lsN, "Line Space patches per face edge N (methods bvh+ls*)")->capture_default_str();
    c.add_option("--ls-depth", o.lsDepth, "Line Space BVH depth D")->capture_default_str();
    c.add_option("--ls-t", o.lsT, "Line Space triangle threshold T")->capture_default_str();
    c.add_option("--ls-angle", o.lsAngle, "Candidate normal-angle threshold in degrees")->capture_default_str();
    c.add_option("--ls-ntree", o.lsNtree, "N-tree with binary Line Spaces N:d for method ntree+ls (default 6:3)");
    c.add_option("--ls-ntree-level", o.lsNtreeLevel,
                 "ntree+ls: N-tree level whose occupied shafts count as occluded (default d-1 as SS; >= d: exact)");
    c.add_option("--ls-ntree-near", o.lsNtreeNear,
                 "ntree+ls: shadow-level nodes entered within this many node edges of the ray origin are handled "
                 "like the start node (0 = SS 4.1)")
        ->capture_default_str();
    c.add_option("--ls-ntree-start", o.lsNtreeStart,
                 "ntree+ls: the node a shadow ray starts or ends in: skip (SS 4.1) or exact (triangle tests)")
        ->capture_default_str();
    c.add_option("--ls-modes", o.lsModes,
                 "Line Space mode per ray type, e.g. primary=exact,shadow=shadow,ao=candidate,diffuse=candidate,"
                 "bounce=shadow,faces=front-start (modes: off, exact, shadow, candidate, candidate-exact-start; faces: "
                 "front-start, front, both)");
    c.add_option("--ls-cache", o.lsCache, "Line Space and N-tree cache directory (empty: no cache)")->capture_default_str();
    c.add_flag("--out-of-core", o.outOfCore,
               "Prepared scenes (.chs): chcrt methods trace through a GPU subtree cache fed from the file "
               "(CHC+RT §5.4) instead of the in-core BVH");
    c.add_option("--gpu-cache-mb", o.gpuCacheMb, "Out of core: GPU subtree cache budget in MiB")->capture_default_str();
    c.add_option("--host-cache-mb", o.hostCacheMb, "Out of core: host subtree cache budget in MiB")->capture_default_str();
    c.add_option("--uploads-per-trace", o.uploadsPerTrace,
                 "Out of core: subtrees uploaded per trace at most; the rest waits for later frames (0 = no limit, "
                 "exact frames; default 0, interactive viewer 16)")
        ->check(CLI::NonNegativeNumber);
    c.add_option("--cache-policy", o.cachePolicy, "Out of core: GPU cache replacement, round-robin or lru")
        ->capture_default_str();
    c.add_option("--load-in-core", o.loadInCore,
                 "Out of core: also load the scene in core for pure-BVH references and id-indexed shading: on, off, "
                 "or auto (on when it takes less than a quarter of the RAM)")
        ->capture_default_str();
}

RenderSettings toRenderSettings(const CommonOptions& o, int defaultSpp) {
    RenderSettings s;
    s.width = o.width;
    s.height = o.height;
    s.samplesPerPixel = o.spp > 0 ? o.spp : defaultSpp;
    if (o.spp == 0 || o.spp < -1) throw InputError("--spp must be at least 1");
    s.effects = parseEffects(o.effects);
    s.seed = o.seed;
    s.rotationDegrees = o.rotation;
    s.aoLengthFraction = o.aoLength;
    s.exposure = o.exposure;
    s.primaryVisibility = parsePrimaryVisibility(o.primary);
    validateSettings(s);
    return s;
}

BvhBuildOptions toBvhOptions(const CommonOptions& o) {
    if (o.bvhLeafSize < 1 || o.bvhLeafSize > 64) throw InputError("--bvh-leaf-size must be between 1 and 64");
    if (o.bvhBins < 2 || o.bvhBins > 256) throw InputError("--bvh-bins must be between 2 and 256");
    BvhBuildOptions b;
    b.maxLeafTriangles = o.bvhLeafSize;
    b.binCount = o.bvhBins;
    return b;
}

glm::vec3 parseVec3(const std::string& text, const char* flag) {
    std::stringstream stream(text);
    glm::vec3 v;
    char comma1 = 0, comma2 = 0;
    stream >> v.x >> comma1 >> v.y >> comma2 >> v.z;
    if (!stream || comma1 != ',' || comma2 != ',' || !(stream >> std::ws).eof() || !std::isfinite(v.x) ||
        !std::isfinite(v.y) || !std::isfinite(v.z)) {
        throw InputError(std::string(flag) + " expects three finite numbers x,y,z, got '" + text + "'");
    }
    return v;
}

} // namespace chcrt::app
