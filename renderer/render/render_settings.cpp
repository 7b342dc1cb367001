#include "renderer/render/render_settings.h"

#include "renderer/core/error.h"

#include <cmath>
#include <sstream>

namespace chcrt {

RayType parseRayType(const std::string& name) {
    if (name == "primary") return RayType::Primary;
    if (name == "shadow") return RayType::Shadow;
    if (name == "ao") return RayType::Ao;
    if (name == "diffuse") return RayType::Diffuse;
    throw InputError("unknown ray type '" + name + "' (expected primary, shadow, ao or diffuse)");
}

const char* toString(RayType type) {
    switch (type) {
    case RayType::Primary: return "primary";
    case RayType::Shadow: return "shadow";
    case RayType::Ao: return "ao";
    case RayType::Diffuse: return "diffuse";
    }
    return "?";
}

PrimaryVisibility parsePrimaryVisibility(const std::string& name) {
    if (name == "raster") return PrimaryVisibility::Raster;
    if (name == "traced") return PrimaryVisibility::Traced;
    throw InputError("unknown primary visibility '" + name + "' (expected raster or traced)");
}

const char* toString(PrimaryVisibility primary) {
    return primary == PrimaryVisibility::Traced ? "traced" : "raster";
}

EffectSet parseEffects(const std::string& list) {
    EffectSet effects{false, false, false};
    if (list == "none") return effects;
    if (list == "all") return EffectSet{};
    std::stringstream stream(list);
    std::string item;
    bool any = false;
    while (std::getline(stream, item, ',')) {
        if (item == "shadow" || item == "shadows") effects.shadows = true;
        else if (item == "ao") effects.ao = true;
        else if (item == "diffuse") effects.diffuse = true;
        else throw InputError("unknown effect '" + item + "' in --effects (expected shadow, ao, diffuse, all or none)");
        any = true;
    }
    if (!any) throw InputError("--effects is empty (use 'none' for no secondary effects)");
    return effects;
}

std::string toString(const EffectSet& effects) {
    std::string out;
    auto add = [&](bool on, const char* name) {
        if (!on) return;
        if (!out.empty()) out += ",";
        out += name;
    };
    add(effects.shadows, "shadow");
    add(effects.ao, "ao");
    add(effects.diffuse, "diffuse");
    return out.empty() ? "none" : out;
}

void validateSettings(const RenderSettings& s) {
    if (s.width < 1 || s.height < 1 || s.width > 16384 || s.height > 16384)
        throw InputError("image size must be between 1 and 16384 pixels per side");
    if (s.samplesPerPixel < 1 || s.samplesPerPixel > 4096)
        throw InputError("--spp must be between 1 and 4096");
    if (!(s.rotationDegrees >= 0.0f && s.rotationDegrees <= 360.0f))
        throw InputError("--rotation must be between 0 and 360 degrees");
    if (!(s.aoLengthFraction > 0.0f && std::isfinite(s.aoLengthFraction)))
        throw InputError("--ao-length must be a positive fraction of the scene diagonal");
    if (!(s.diffuseLengthFraction > 0.0f && std::isfinite(s.diffuseLengthFraction)))
        throw InputError("--diffuse-length must be a positive fraction of the scene diagonal");
    if (!(s.exposure > 0.0f && std::isfinite(s.exposure)))
        throw InputError("--exposure must be positive");
}

} // namespace chcrt
