#pragma once
// Everything the viewer's panel, keys and scripts can change, in one struct built on the CLI's CommonOptions:
// one place turns it into the renderer's RenderSettings and into the `chcrt render` / `chcrt bench` command
// lines that reproduce the current view. Parameters are set and printed through the
// parameter table (app/parameters.h), as the CLI parses them.
#include "app/methods.h"
#include "app/options.h"
#include "app/viewer/view_modes.h"
#include "renderer/render/render_settings.h"
#include "renderer/scene/scene.h"

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace chcrt::app {

// "raster": G-buffer and unshadowed direct light only (no secondary rays; with primary "traced" the G-buffer's
// primary rays are traced with pure BVH). Every other name is a GPU tracing method of the registry
// (app/methods.h).
inline constexpr const char* kRasterOnlyMethod = "raster";
std::vector<std::string> viewerMethods();

struct ViewerSettings {
    CommonOptions common;          // effects, spp, seed, rotation, AO length, exposure, primary visibility;
                                   // width/height = window
    std::string method = "bvh";    // kRasterOnlyMethod or a gpuMethods() name
    ViewMode viewMode = ViewMode::Shaded;
    // CHC+RT methods without their adaptive fallback to a pure BVH pass (app/methods.h makeTracer), so that the
    // culling itself is what runs and is timed.
    bool chcrtAlwaysCull = false;
    RayType costRayType = RayType::Primary; // rays whose traversal cost the cost view shows
    float costScale = 1000.0f;     // traversal steps at the top of the (logarithmic) heat map
    float renderScale = 0.5f;      // internal resolution / window resolution
    bool accumulate = true;        // progressive refinement while the camera and settings stay unchanged
    int maxAccumulatedFrames = 64;
    // Refinement frames after the first use seeds seed+1, seed+2, ...; with full rotation (360°, CHC+RT §5.3)
    // the per-pixel perturbation covers the whole sample domain, so the average converges to the integral and
    // not only to the neighbourhood of each pass's shared sample.
    bool refineWithFullRotation = true;
    // Set by the viewer for an --out-of-core scene that is not loaded in core (docs/outofcore.md): primary
    // visibility is always traced (out-of-core primary rays) and the diffuse effect is off, as in `chcrt render`.
    bool sceneNotInCore = false;
};

// Internal render resolution for a window (framebuffer) size: at least 1×1.
void internalSize(const ViewerSettings& settings, int windowWidth, int windowHeight, int& width, int& height);
// The renderer settings of refinement frame `accumulatedFrame` (0 = the plain frame, as `chcrt render` draws it).
RenderSettings toRenderSettings(const ViewerSettings& settings, int width, int height, int accumulatedFrame);

// Applies {"name": value, ...}: the viewer's own settings (method, viewMode, chcrtAlwaysCull, renderScale,
// accumulate, maxAccumulatedFrames, refineWithFullRotation, costRayType, costScale) and every parameter of the
// table with a viewer key (app/parameters.cpp: primary, effects, spp, seed, rotation, aoLength, exposure, the
// chcrt*, ls* and lsNtree* method parameters; -1 gives a method parameter back to the method's default).
// Validates everything before changing anything; throws InputError naming the key.
void applySettings(ViewerSettings& settings, const nlohmann::json& changes);

// The registered method of the settings (app/methods.h); nullptr for the raster-only method.
const MethodInfo* viewerMethod(const ViewerSettings& settings);
// The method parameters the settings' method runs with on a scene of `sceneTriangles` triangles: its defaults
// with the given ones on top (what the panel shows and the shafts view uses).
CommonOptions shownParameters(const ViewerSettings& settings, uint64_t sceneTriangles);

// The tracing methods' parameters of `common` (CHC+RT --chcrt-*, Line Space --ls-*) as one string: the viewer
// recreates the tracer when it changes (methods read them from SceneSession::options, app/methods.cpp).
std::string methodParameters(const CommonOptions& common);
// Copies those parameters (only) from `from` into `to`.
void copyMethodParameters(const CommonOptions& from, CommonOptions& to);

// `chcrt render ...` reproducing the current camera and settings at the internal resolution (the first,
// unaccumulated frame), and the `chcrt bench ...` line timing the same rays per method.
std::string renderCommandLine(const ViewerSettings& settings, const Camera& camera, int width, int height);
std::string benchCommandLine(const ViewerSettings& settings, const Camera& camera, int width, int height);

} // namespace chcrt::app
