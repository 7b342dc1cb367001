#pragma once
// Every flag of CommonOptions, described once (parameterTable(), app/parameters.cpp): its name, help, value
// syntax and range, the viewer setting it is (script key and panel widget), when a copied command line carries
// it, and the field it sets in its area's typed home. Everything that handles these flags iterates the table:
// CLI registration and validation (app/options.cpp), the methods' overrides (app/methods.cpp), the viewer's
// settings, panel and copied command lines (app/viewer/). docs/architecture.md, "Worked example: adding a CHC+RT
// parameter", shows what a new parameter touches.
#include "app/options.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace chcrt::app {

// Groups of parameters: a CLI11 option group each, a panel section, and what a tracing method reads
// (MethodInfo::areas, app/methods.h).
enum class ParameterArea : uint8_t {
    Session,         // scene, camera, frames, GL context, outputs: CommonOptions' own fields
    Render,          // CommonOptions::render (RenderSettings)
    Bvh,             // CommonOptions::bvh (BvhBuildOptions)
    Chcrt,           // CommonOptions::chcrt (ChcrtOptions): the chcrt* methods
    ChcrtVisibility, // ChcrtOptions::visibleThreshold: approximate culling (chcrt-aggressive)
    LineSpace,       // CommonOptions::lineSpace, lineSpaceTracing: bvh+ls*, chcrt+ls*
    LineSpaceModes,  // LineSpaceTracing::modes: bvh+ls* (chcrt+ls* fix their modes)
    NTree,           // CommonOptions::ntree, ntreeShadow: ntree+ls
    LineSpaceCache,  // --ls-cache: the methods that build Line Spaces or N-trees
    OutOfCore,       // CommonOptions::outOfCore, outOfCoreScene: prepared scenes traced out of core
    Lod,             // OutOfCoreOptions::lodPixels: level-of-detail proxies (chcrt-lod)
};
const char* toString(ParameterArea area); // the option group's title in --help
// Areas whose values are a tracing method's parameters (the method's own defaults apply to what is not given).
bool isMethodArea(ParameterArea area);

// When the viewer's copied command lines carry a parameter (its area must apply: commandLineArguments).
enum class Emit : uint8_t {
    Never,        // the line has it in its own place (--scene, --width) or not at all (--stats-json)
    Always,       // --spp, --seed: the reproduction needs them
    IfGiven,      // method parameters: set by the user, else the method's default
    IfNotDefault, // differs from CommonOptions' default
};

// The viewer panel's widget of a parameter (drawn by app/viewer/viewer_ui.cpp).
struct ParameterWidget {
    enum class Kind : uint8_t {
        None,        // not in the panel
        Slider,      // SliderInt for integers, SliderFloat for numbers
        LogSlider,   // logarithmic SliderFloat
        InputInt,
        Checkbox,    // on/off parameters
        Combo,       // one of Parameter::choices
        PairSliders, // "A:B" parameters (--ls-ntree N:d): a slider each
        Custom,      // drawn by the panel itself (effects, primary visibility)
    };
    Kind kind = Kind::None;
    const char* label = nullptr;
    float min = 0.0f, max = 0.0f;
    const char* format = nullptr; // SliderFloat format
    bool sameLine = false;        // on the line of the previous widget
    const char* secondLabel = nullptr; // PairSliders
    float secondMin = 0.0f, secondMax = 0.0f;
};

struct Parameter {
    std::string flag;      // "--chcrt-min-tile" (the name in CommonOptions::given)
    std::string names;     // CLI11 names when they differ from `flag` ("-q,--quiet")
    std::string key;       // viewer setting and script key ("chcrtMinTile"); empty: not changeable live
    ParameterArea area = ParameterArea::Session;
    std::string help;
    std::string valueName; // "N", "on|off", ... in --help
    std::string defaultNote; // per-method or derived defaults, said in --help ("d - 1")
    Emit emit = Emit::Never;
    uint8_t commands = kEveryCommand; // CommandSet bits a command needs to have the flag
    bool isFlag = false;       // a CLI flag without value (--out-of-core, -q); JSON true/false
    bool minusOneUnsets = false; // -1 (flag or viewer setting) = not given: the method's default applies
    std::vector<std::string> choices; // the values of a choice parameter (Combo, --help)
    ParameterWidget widget;

    // Access to the field (built by the typed helpers in parameters.cpp; use the functions below).
    std::function<void(CommonOptions&, const std::string& text)> parseText;     // validates: InputError naming the flag
    std::function<void(CommonOptions&, const nlohmann::json&)> parseJson;       // validates: InputError naming the key
    std::function<std::string(const CommonOptions&)> text;                      // the value as a command-line word
    std::function<nlohmann::json(const CommonOptions&)> json;                   // the value as a viewer setting
    std::function<void(const CommonOptions& from, CommonOptions& to)> copy;     // the field only
};

const std::vector<Parameter>& parameterTable();
// nullptr when no parameter has that flag / viewer key.
const Parameter* findParameter(const std::string& flag);
const Parameter* findParameterByKey(const std::string& key);

// Sets a parameter from a command-line word or a viewer setting: validates, stores it and marks it given; -1 of a
// minusOneUnsets parameter (and JSON null) unsets it (its CommonOptions default, not given).
void setParameter(CommonOptions& options, const Parameter& parameter, const std::string& text);
void setParameter(CommonOptions& options, const Parameter& parameter, const nlohmann::json& value);

// Copies the values and given marks of the parameters `which` accepts.
void copyParameters(const CommonOptions& from, CommonOptions& to, const std::function<bool(const Parameter&)>& which);
// "flag=text" of each given parameter `which` accepts, space-separated in table order (a key for what changed).
std::string givenParameters(const CommonOptions& options, const std::function<bool(const Parameter&)>& which);

// The "--flag value" words of a command line reproducing `options`: parameters whose area `applies` and whose
// Emit rule holds, in table order (each word led by a space). Flags without value appear alone.
std::string commandLineArguments(const CommonOptions& options, const std::function<bool(ParameterArea)>& applies);

// Quotes a shell word when it holds anything but safe characters.
std::string shellWord(const std::string& word);
// The shortest text that reads back as the same float.
std::string formatFloat(float value);

} // namespace chcrt::app
