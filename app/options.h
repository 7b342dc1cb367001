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
};

// Adds the shared options to a subcommand. `withEffects`: the command renders shaded images.
void addCommonOptions(CLI::App& command, CommonOptions& options, bool withEffects);

RenderSettings toRenderSettings(const CommonOptions& options, int defaultSpp);
BvhBuildOptions toBvhOptions(const CommonOptions& options);

// "x,y,z" → vector; throws InputError naming the flag.
glm::vec3 parseVec3(const std::string& text, const char* flag);

} // namespace chcrt::app
