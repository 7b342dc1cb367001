#include "app/options.h"

#include "app/methods.h"
#include "app/parameters.h"
#include "renderer/core/error.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <map>
#include <sstream>

namespace chcrt::app {
namespace {

// The default a parameter's --help shows: its note, else its value in `options` (the command's defaults) and the
// values the methods reading it start from where they differ (app/methods.h).
std::string defaultText(const Parameter& p, const CommonOptions& options) {
    if (!p.defaultNote.empty()) return p.defaultNote;
    std::string text = p.text(options);
    if (!isMethodArea(p.area)) return text;
    for (const MethodInfo& m : methodRegistry()) {
        if (!m.reads(p.area)) continue;
        const std::string own = p.text(methodDefaults(m, options, 0));
        if (own != p.text(options)) text += "; " + m.name + ": " + own;
    }
    return text;
}

} // namespace

void addCommonOptions(CLI::App& command, CommonOptions& o, uint8_t commands) {
    // Option groups in the order of the areas.
    std::map<ParameterArea, CLI::Option_group*> groups;
    for (const Parameter& p : parameterTable()) groups[p.area] = nullptr;
    for (auto& [area, group] : groups) group = command.add_option_group(toString(area));
    for (const Parameter& p : parameterTable()) {
        if ((p.commands & ~commands) != 0) continue;
        CLI::Option_group* group = groups[p.area];
        const std::string names = p.names.empty() ? p.flag : p.names;
        if (p.isFlag) {
            group->add_flag_callback(names, [&o, &p] { setParameter(o, p, std::string("on")); }, p.help);
            continue;
        }
        CLI::Option* option = group->add_option_function<std::string>(
            names, [&o, &p](const std::string& text) { setParameter(o, p, text); }, p.help);
        if (!p.valueName.empty()) option->type_name(p.valueName);
        const std::string shown = defaultText(p, o);
        if (!shown.empty()) option->default_str(shown);
    }
}

RenderSettings toRenderSettings(const CommonOptions& o, int defaultSpp) {
    RenderSettings s = o.render;
    if (!o.isGiven("--spp")) s.samplesPerPixel = defaultSpp;
    validateSettings(s);
    return s;
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
