#pragma once
// The renderer's settings: one struct that the CLI flags, the viewer's panel and config files all edit, so any
// state can be printed as the command line that reproduces it (settingsToCommandLine).
#include <cstdint>
#include <string>
#include <vector>

namespace chcrt {

enum class RayType { Primary, Shadow, Ao, Diffuse };

// "primary" | "shadow" | "ao" | "diffuse"; throws InputError otherwise.
RayType parseRayType(const std::string& name);
const char* toString(RayType type);
// True for ray types traced with any-hit queries (shadow, AO): only hit/miss matters.
inline bool isAnyHit(RayType type) { return type == RayType::Shadow || type == RayType::Ao; }

struct EffectSet {
    bool shadows = true;
    bool ao = true;
    bool diffuse = true;
};
// "shadow,ao,diffuse" (any subset, also "none" / "all"); throws InputError for unknown names.
EffectSet parseEffects(const std::string& list);
std::string toString(const EffectSet& effects);

// How the G-buffer (primary visibility) is made. Raster: rasterise the clusters inside the frustum. Traced:
// generate one primary ray per pixel, trace it with the active Tracer (pure BVH, CHC+RT, ...; CHC+RT §5 "Prim")
// and resolve the hit buffer into the same G-buffer targets, so that out-of-core scenes never rasterise the
// whole scene. Everything after the G-buffer is the same for both.
enum class PrimaryVisibility { Raster, Traced };
// "raster" | "traced"; throws InputError otherwise.
PrimaryVisibility parsePrimaryVisibility(const std::string& name);
const char* toString(PrimaryVisibility primary);

struct RenderSettings {
    int width = 512;
    int height = 512;
    int samplesPerPixel = 4; // N samples = N passes per effect, accumulated (CHC+RT §5.3)
    EffectSet effects;
    uint32_t seed = 1;
    // Per-pixel random rotation of the pass's shared sample (CHC+RT §5.3, Table 5): 0, 18, 36 or 360 (full).
    float rotationDegrees = 36.0f;
    // AO ray length as a fraction of the scene's bounding-box diagonal ("short rays").
    float aoLengthFraction = 0.02f;
    // Diffuse rays reach the whole scene: length = diagonal × this.
    float diffuseLengthFraction = 1.0f;
    float exposure = 1.0f;
    float skyAmbient = 0.35f; // ambient sky radiance scaled by AO
    float originOffset = 2e-4f; // secondary ray origin offset per unit of view distance
    PrimaryVisibility primaryVisibility = PrimaryVisibility::Raster;
};

// Throws InputError naming the field for out-of-range values (size, spp, rotation, lengths).
void validateSettings(const RenderSettings& settings);

} // namespace chcrt
