#include "app/parameters.h"

#include "renderer/core/error.h"
#include "renderer/core/memory_budget.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string_view>

namespace chcrt::app {
namespace {

// A field of CommonOptions, for const and mutable options alike: FIELD(chcrt.pairs.minTileSize).
#define FIELD(path) [](auto& o) -> auto& { return o.path; }

// How one type's values are read from a command-line word or a viewer setting and written back. `name` is the
// flag or the viewer key, for the error messages.
template <typename T>
struct Codec {
    std::function<T(const std::string& text, const std::string& name)> parse;
    std::function<T(const nlohmann::json& value, const std::string& name)> fromJson;
    std::function<std::string(const T&)> text;
    std::function<nlohmann::json(const T&)> json;
};

[[noreturn]] void wrongType(const nlohmann::json& value, const std::string& key) {
    throw InputError("viewer setting '" + key + "' has the wrong type: " + value.dump());
}

// Range check of a number: "--spp must be at least 1", "--ls-angle must be between 0 and 180".
template <typename T>
void checkRange(T value, double lo, double hi, const std::string& name, const std::string& shown) {
    if (double(value) >= lo && double(value) <= hi) return;
    const auto number = [](double v) { return formatFloat(float(v)); };
    if (hi >= double(std::numeric_limits<int32_t>::max())) throw InputError(name + " must be at least " + number(lo));
    throw InputError(name + " must be between " + number(lo) + " and " + number(hi) + ", not " + shown);
}

template <typename T>
Codec<T> integerCodec(double lo, double hi) {
    Codec<T> c;
    c.parse = [lo, hi](const std::string& text, const std::string& name) {
        long long value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || end != text.data() + text.size()) {
            throw InputError(name + " expects a whole number, got '" + text + "'");
        }
        checkRange(value, lo, hi, name, text);
        return T(value);
    };
    c.fromJson = [lo, hi](const nlohmann::json& value, const std::string& name) {
        if (!value.is_number_integer()) wrongType(value, name);
        const long long v = value.get<long long>();
        checkRange(v, lo, hi, name, value.dump());
        return T(v);
    };
    c.text = [](const T& v) { return std::to_string(v); };
    c.json = [](const T& v) { return nlohmann::json(v); };
    return c;
}

Codec<float> floatCodec(double lo, double hi) {
    Codec<float> c;
    c.parse = [lo, hi](const std::string& text, const std::string& name) {
        char* end = nullptr;
        const float value = std::strtof(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value)) {
            throw InputError(name + " expects a number, got '" + text + "'");
        }
        checkRange(value, lo, hi, name, text);
        return value;
    };
    c.fromJson = [lo, hi](const nlohmann::json& value, const std::string& name) {
        if (!value.is_number()) wrongType(value, name);
        const float v = value.get<float>();
        checkRange(v, lo, hi, name, value.dump());
        return v;
    };
    c.text = [](const float& v) { return formatFloat(v); };
    c.json = [](const float& v) { return nlohmann::json(v); };
    return c;
}

// Megabytes on the command line, bytes in the field (OutOfCoreOptions' budgets).
Codec<uint64_t> megabyteCodec() {
    // At most 10^12 MB (an exabyte): the shift to bytes must not overflow 64 bits (2^44 MB would).
    const Codec<uint64_t> mb = integerCodec<uint64_t>(1, 1e12);
    Codec<uint64_t> c;
    c.parse = [mb](const std::string& text, const std::string& name) { return mb.parse(text, name) << 20; };
    c.fromJson = [mb](const nlohmann::json& value, const std::string& name) { return mb.fromJson(value, name) << 20; };
    c.text = [](const uint64_t& bytes) { return std::to_string(bytes >> 20); };
    c.json = [](const uint64_t& bytes) { return nlohmann::json(bytes >> 20); };
    return c;
}

// --max-memory-mb: like megabyteCodec, but 0 (the default, decided from the machine at run time) has no text, so a
// copied command line leaves the flag out rather than writing a value the flag refuses.
Codec<uint64_t> memoryBudgetCodec() {
    Codec<uint64_t> c = megabyteCodec();
    c.text = [](const uint64_t& bytes) { return bytes == 0 ? std::string() : std::to_string(bytes >> 20); };
    return c;
}

// One of named values: "--cache-policy must be round-robin or lru, not 'fifo'".
template <typename T>
Codec<T> choiceCodec(std::vector<std::pair<std::string, T>> values) {
    const auto find = [values](const std::string& text, const std::string& name) {
        std::string list;
        for (size_t i = 0; i < values.size(); ++i) {
            if (values[i].first == text) return values[i].second;
            list += (i == 0 ? "" : i + 1 == values.size() ? " or " : ", ") + values[i].first;
        }
        throw InputError(name + " must be " + list + ", not '" + text + "'");
    };
    Codec<T> c;
    c.parse = find;
    c.fromJson = [find](const nlohmann::json& value, const std::string& name) {
        if (!value.is_string()) wrongType(value, name);
        return find(value.get<std::string>(), name);
    };
    c.text = [values](const T& v) {
        for (const auto& [text, value] : values) {
            if (value == v) return text;
        }
        return std::string("?");
    };
    c.json = [text = c.text](const T& v) { return nlohmann::json(text(v)); };
    return c;
}

// --gl-device: an EGL device index, or auto (kAutoGlDevice).
Codec<int> glDeviceCodec() {
    const auto fail = [](const std::string& shown, const std::string& name) -> int {
        throw InputError(name + " must be auto or an EGL device index (chcrt info --devices lists them), not " + shown);
    };
    Codec<int> c;
    c.parse = [fail](const std::string& text, const std::string& name) {
        if (text == "auto") return kAutoGlDevice;
        int value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < 0 || value > 1024) {
            return fail("'" + text + "'", name);
        }
        return value;
    };
    c.fromJson = [fail](const nlohmann::json& value, const std::string& name) {
        if (value.is_string() && value.get<std::string>() == "auto") return kAutoGlDevice;
        if (!value.is_number_integer() || value.get<long long>() < 0 || value.get<long long>() > 1024) {
            return fail(value.dump(), name);
        }
        return value.get<int>();
    };
    c.text = [](const int& v) { return v == kAutoGlDevice ? std::string("auto") : std::to_string(v); };
    c.json = [](const int& v) { return v == kAutoGlDevice ? nlohmann::json("auto") : nlohmann::json(v); };
    return c;
}

// on|off on the command line, true/false as a viewer setting.
Codec<bool> onOffCodec() {
    Codec<bool> c = choiceCodec<bool>({{"on", true}, {"off", false}});
    c.fromJson = [](const nlohmann::json& value, const std::string& name) {
        if (!value.is_boolean()) wrongType(value, name);
        return value.get<bool>();
    };
    c.json = [](const bool& v) { return nlohmann::json(v); };
    return c;
}

// Text, checked by `validate` (which throws InputError) when not empty.
Codec<std::string> textCodec(std::function<void(const std::string&)> validate = nullptr) {
    Codec<std::string> c;
    c.parse = [validate](const std::string& text, const std::string&) {
        if (validate && !text.empty()) validate(text);
        return text;
    };
    c.fromJson = [validate](const nlohmann::json& value, const std::string& name) {
        if (!value.is_string()) wrongType(value, name);
        const std::string text = value.get<std::string>();
        if (validate && !text.empty()) validate(text);
        return text;
    };
    c.text = [](const std::string& v) { return v; };
    c.json = [](const std::string& v) { return nlohmann::json(v); };
    return c;
}

// A value with its own text form: effects ("shadow,ao"), N-trees ("6:3").
template <typename T>
Codec<T> formattedCodec(std::function<T(const std::string&)> parse, std::function<std::string(const T&)> format) {
    Codec<T> c;
    c.parse = [parse](const std::string& text, const std::string&) { return parse(text); };
    c.fromJson = [parse](const nlohmann::json& value, const std::string& name) {
        if (!value.is_string()) wrongType(value, name);
        return parse(value.get<std::string>());
    };
    c.text = format;
    c.json = [format](const T& v) { return nlohmann::json(format(v)); };
    return c;
}

// A parameter under construction: the description, then the field and codec it reads and writes.
class Describe {
public:
    Describe(ParameterArea area, std::string flag, std::string key, std::string help) {
        p_.area = area;
        p_.flag = std::move(flag);
        p_.key = std::move(key);
        p_.help = std::move(help);
        p_.emit = isMethodArea(area) ? Emit::IfGiven : Emit::Never;
    }
    Describe& names(std::string names) { p_.names = std::move(names); return *this; }
    Describe& value(std::string name) { p_.valueName = std::move(name); return *this; }
    Describe& defaults(std::string note) { p_.defaultNote = std::move(note); return *this; }
    Describe& emit(Emit emit) { p_.emit = emit; return *this; }
    Describe& commands(uint8_t commands) { p_.commands = commands; return *this; }
    Describe& minusOneUnsets() { p_.minusOneUnsets = true; return *this; }
    Describe& flagWithoutValue() { p_.isFlag = true; return *this; }
    Describe& widget(ParameterWidget::Kind kind, const char* label, float lo = 0, float hi = 0, const char* format = nullptr) {
        p_.widget.kind = kind;
        p_.widget.label = label;
        p_.widget.min = lo;
        p_.widget.max = hi;
        p_.widget.format = format;
        return *this;
    }
    Describe& slider(const char* label, float lo, float hi, const char* format = nullptr) {
        return widget(ParameterWidget::Kind::Slider, label, lo, hi, format);
    }
    Describe& logSlider(const char* label, float lo, float hi, const char* format) {
        return widget(ParameterWidget::Kind::LogSlider, label, lo, hi, format);
    }
    Describe& checkbox(const char* label, bool sameLine = false) {
        widget(ParameterWidget::Kind::Checkbox, label);
        p_.widget.sameLine = sameLine;
        return *this;
    }
    Describe& pairSliders(const char* label, float lo, float hi, const char* secondLabel, float secondLo, float secondHi) {
        widget(ParameterWidget::Kind::PairSliders, label, lo, hi);
        p_.widget.secondLabel = secondLabel;
        p_.widget.secondMin = secondLo;
        p_.widget.secondMax = secondHi;
        return *this;
    }

    // The field and how its values read and write.
    template <typename T, typename Field>
    Parameter sets(Field field, Codec<T> codec) const {
        Parameter p = p_;
        const std::string flag = p.flag, key = p.key.empty() ? p.flag : p.key;
        p.parseText = [field, codec, flag](CommonOptions& o, const std::string& text) { field(o) = codec.parse(text, flag); };
        p.parseJson = [field, codec, key](CommonOptions& o, const nlohmann::json& v) { field(o) = codec.fromJson(v, key); };
        p.text = [field, codec](const CommonOptions& o) { return codec.text(field(o)); };
        p.json = [field, codec](const CommonOptions& o) { return codec.json(field(o)); };
        p.copy = [field](const CommonOptions& from, CommonOptions& to) { field(to) = field(from); };
        return p;
    }
    template <typename T, typename Field>
    Parameter integer(Field field, double lo, double hi = 2147483647.0) const {
        return named("INT").sets<T>(field, integerCodec<T>(lo, hi));
    }
    template <typename Field>
    Parameter number(Field field, double lo = -1e30, double hi = 1e30) const {
        return named("FLOAT").sets<float>(field, floatCodec(lo, hi));
    }
    template <typename Field>
    Parameter onOff(Field field) const {
        Describe d = *this;
        if (d.p_.valueName.empty() && !d.p_.isFlag) d.p_.valueName = "on|off";
        return d.sets<bool>(field, onOffCodec());
    }
    template <typename T, typename Field>
    Parameter choice(Field field, std::vector<std::pair<std::string, T>> values) const {
        Describe d = *this;
        std::string names;
        for (const auto& [name, value] : values) {
            d.p_.choices.push_back(name);
            names += (names.empty() ? "" : "|") + name;
        }
        if (d.p_.valueName.empty()) d.p_.valueName = names;
        return d.sets<T>(field, choiceCodec<T>(std::move(values)));
    }
    template <typename Field>
    Parameter text(Field field, std::function<void(const std::string&)> validate = nullptr) const {
        return sets<std::string>(field, textCodec(std::move(validate)));
    }

private:
    Describe named(const char* valueName) const { // the value's name in --help unless one is given
        Describe d = *this;
        if (d.p_.valueName.empty()) d.p_.valueName = valueName;
        return d;
    }

    Parameter p_;
};

using Kind = ParameterWidget::Kind;
using Area = ParameterArea;

std::vector<Parameter> describeSession() {
    return {
        Describe(Area::Session, "--scene", "",
                 "Scene: a .gltf/.glb/.ply/.obj file or a generator spec (city, interior, plant, plane-and-box, "
                 "closed-box, one-triangle; e.g. city:2m:seed=3)")
            .text(FIELD(scene)),
        Describe(Area::Session, "--camera-path", "",
                 "Walkthrough JSON file, or near/far for a generated scene's street-level/bird's-eye path")
            .defaults("near for generated scenes, the default camera otherwise")
            .text(FIELD(cameraPath)),
        Describe(Area::Session, "--camera", "", "A camera stored in a glTF file: gltf:<index or name>").text(FIELD(camera)),
        Describe(Area::Session, "--eye", "", "Explicit camera position x,y,z (with --target; overrides paths)")
            .text(FIELD(eye)),
        Describe(Area::Session, "--target", "", "Explicit camera target x,y,z").text(FIELD(target)),
        Describe(Area::Session, "--fov", "", "Vertical field of view in degrees for --eye/--target").number(FIELD(fovY)),
        Describe(Area::Session, "--frames", "",
                 "Frames of the path: all, all:10 (every 10th), 7, 1-100, 1-100:10, 3,5-9, spread:5 (0-based)")
            .defaults("render 0; bench and verify spread:5")
            .text(FIELD(frames)),
        Describe(Area::Session, "--gl", "", "OpenGL context: egl (headless) or osmesa")
            .commands(kHeadlessCommands)
            .choice<GlBackend>(FIELD(gl), {{"egl", GlBackend::Egl}, {"osmesa", GlBackend::OsMesa}}),
        Describe(Area::Session, "--gl-device", "",
                 "EGL device to render on: its index in the EGL device list (chcrt info --devices; no fall-back to "
                 "another device or platform), or auto: the first hardware device that creates a context, else a "
                 "software one or Mesa's surfaceless platform, with a warning")
            .commands(kHeadlessCommands)
            .value("N|auto")
            .sets<int>(FIELD(glDevice), glDeviceCodec()),
        Describe(Area::Session, "--shader-stage", "",
                 "Shader stage of pure BVH tracing (method bvh, the pure passes inside the other methods, the "
                 "references of bench and verify) and of CHC+RT's cell passes (bounds-only, bounds-gpu): fragment "
                 "(a full-screen pass, points over the cells), compute (an invocation per ray; the same hits bit for "
                 "bit) or auto: fragment on software renderers (llvmpipe, where fragments measured faster), compute "
                 "on every other; the environment variable CHCRT_SHADER_STAGE overrides auto. Line Space, N-tree "
                 "shadow and CHC+RT's gl query and subtree passes stay fragment passes")
            .emit(Emit::IfNotDefault)
            .choice<TraceStage>(FIELD(shaderStage), {{"auto", TraceStage::Auto},
                                                     {"fragment", TraceStage::Fragment},
                                                     {"compute", TraceStage::Compute}}),
        Describe(Area::Session, "--strict", "",
                 "Refuse scenes that load with warnings (a missing texture file, faces of fewer than 3 vertices, a "
                 "file cut short) instead of printing the warnings")
            .flagWithoutValue()
            .onOff(FIELD(strict)),
        Describe(Area::Session, "--gl-debug", "", "Print KHR_debug messages from the driver")
            .flagWithoutValue()
            .onOff(FIELD(glDebug)),
        Describe(Area::Session, "--stats-json", "", "Write per-frame statistics as JSON to this file").text(FIELD(statsJson)),
        Describe(Area::Session, "--quiet", "", "No progress bars").names("-q,--quiet").flagWithoutValue().onOff(FIELD(quiet)),
        Describe(Area::Session, "--max-memory-mb", "",
                 "Memory in MiB one run may use for its big buffers (scene, BVH, render targets, Line Spaces, "
                 "out-of-core caches, textures): their estimate is checked before they are allocated")
            .value("MB")
            .defaults("4/5 of the physical memory, " + formatMegabytes(defaultMemoryBudgetBytes()) + " here")
            .sets<uint64_t>(FIELD(maxMemoryBytes), memoryBudgetCodec()),
    };
}

std::vector<Parameter> describeRender() {
    return {
        Describe(Area::Render, "--width", "", "Image width in pixels").integer<int>(FIELD(render.width), -1e9),
        Describe(Area::Render, "--height", "", "Image height in pixels").integer<int>(FIELD(render.height), -1e9),
        Describe(Area::Render, "--spp", "spp", "Samples per pixel per effect (= ray passes)")
            .defaults("render and demo 4; bench, verify and view 1")
            .emit(Emit::Always)
            .slider("spp", 1, 16)
            .integer<int>(FIELD(render.samplesPerPixel), 1),
        Describe(Area::Render, "--effects", "effects", "Secondary effects: any of shadow,ao,diffuse, or all / none")
            .commands(kShadedCommands)
            .widget(Kind::Custom, "effects")
            .sets<EffectSet>(FIELD(render.effects),
                             formattedCodec<EffectSet>(parseEffects, [](const EffectSet& e) { return toString(e); })),
        Describe(Area::Render, "--rotation", "rotation",
                 "Per-pixel random rotation of the shared sample in degrees (0, 18, 36, 360 = full)")
            .emit(Emit::Always)
            .slider("rotation", 0, 360, "%.0f deg")
            .number(FIELD(render.rotationDegrees)),
        Describe(Area::Render, "--ao-length", "aoLength", "AO ray length as a fraction of the scene diagonal")
            .emit(Emit::Always)
            .logSlider("AO length", 0.001f, 0.2f, "%.3f")
            .number(FIELD(render.aoLengthFraction)),
        Describe(Area::Render, "--exposure", "exposure", "Exposure before tone mapping")
            .commands(kShadedCommands)
            .logSlider("exposure", 0.05f, 8.0f, "%.2f")
            .number(FIELD(render.exposure)),
        Describe(Area::Render, "--seed", "seed", "Seed of the per-pixel sample perturbation")
            .emit(Emit::Always)
            .widget(Kind::InputInt, "seed")
            .integer<uint32_t>(FIELD(render.seed), 0, 4294967295.0),
        Describe(Area::Render, "--primary", "primary",
                 "Primary visibility: raster (rasterised G-buffer) or traced (primary rays traced with the method's "
                 "tracer, resolved into the G-buffer)")
            .emit(Emit::IfNotDefault)
            .widget(Kind::Custom, "trace primary rays")
            .choice<PrimaryVisibility>(FIELD(render.primaryVisibility),
                                       {{"raster", PrimaryVisibility::Raster}, {"traced", PrimaryVisibility::Traced}}),
    };
}

std::vector<Parameter> describeBvh() {
    return {
        Describe(Area::Bvh, "--bvh-leaf-size", "", "Maximum triangles per BVH leaf")
            .emit(Emit::IfNotDefault)
            .integer<uint32_t>(FIELD(bvh.maxLeafTriangles), 1, 64),
        Describe(Area::Bvh, "--bvh-bins", "", "SAH bins per axis")
            .emit(Emit::IfNotDefault)
            .integer<uint32_t>(FIELD(bvh.binCount), 2, 256),
    };
}

// CHC+RT (culling/README.md, "Parameters"): each flag sets one ChcrtOptions field; -1 gives the method's default.
std::vector<Parameter> describeChcrt() {
    return {
        Describe(Area::ChcrtVisibility, "--chcrt-threshold", "chcrtThreshold",
                 "CHC+RT §7: a pair is visible only when more rays pass its query (0 = exact; approximate culling, "
                 "chcrt-aggressive only)")
            .minusOneUnsets()
            .slider("visible threshold (rays)", 0, 200)
            .integer<uint32_t>(FIELD(chcrt.visibleThreshold), 0),
        Describe(Area::Chcrt, "--chcrt-min-tile", "chcrtMinTile", "CHC+RT §5.2: minimum screen tile edge in pixels")
            .minusOneUnsets()
            .slider("min tile (px)", 8, 256)
            .integer<int>(FIELD(chcrt.pairs.minTileSize), 1),
        Describe(Area::Chcrt, "--chcrt-height", "chcrtHeight", "CHC+RT §5.2: maximum termination-subtree height")
            .minusOneUnsets()
            .slider("subtree height", 2, 32)
            .integer<uint32_t>(FIELD(chcrt.partition.maxSubtreeHeight), 1),
        Describe(Area::Chcrt, "--chcrt-multi-query", "chcrtMultiQuery",
                 "CHC+RT §5.1: previously invisible pairs per multi-query (1 = off, at most 8)")
            .minusOneUnsets()
            .slider("pairs per multi-query", 1, 16)
            .integer<int>(FIELD(chcrt.multiQueryPairs), 1),
        Describe(Area::Chcrt, "--chcrt-tighter-bounds", "chcrtTighterBounds", "CHC+RT §5.1: query the children's boxes")
            .checkbox("tighter bounds")
            .onOff(FIELD(chcrt.tighterBounds)),
        Describe(Area::Chcrt, "--chcrt-leaf-cache", "chcrtLeafCache",
                 "CHC+RT §5.2: 2-entry leaf cache in subtree traversal (slower on llvmpipe: culling/README.md)")
            .checkbox("leaf cache", true)
            .onOff(FIELD(chcrt.leafCache)),
        Describe(Area::Chcrt, "--chcrt-merged-batch", "chcrtMergedBatch",
                 "CHC+RT: traverse a batch's subtrees as one traversal instead of one after another")
            .checkbox("merged batches", true)
            .onOff(FIELD(chcrt.mergedBatch)),
        Describe(Area::Chcrt, "--chcrt-cell-intersect", "chcrtCellIntersect",
                 "CHC+RT batched: trace each intersection round in one cell pass instead of per-tile subtree passes")
            .checkbox("cell intersection")
            .onOff(FIELD(chcrt.cellIntersect)),
        Describe(Area::Chcrt, "--chcrt-ray-extent", "chcrtRayExtent",
                 "CHC+RT: skip pairs out of reach of their tile's bounded rays")
            .checkbox("ray extent culling")
            .onOff(FIELD(chcrt.rayExtentCulling)),
        Describe(Area::Chcrt, "--chcrt-queries", "chcrtQueries",
                 "CHC+RT: how query pairs are decided: gl (GL occlusion queries, per-tile subtree draws), batched "
                 "(the same test, each round's pairs in one compute dispatch read back once), "
                 "bounds-only (the ray bounds grid decides every pair on the CPU; cell lists, one draw per round) or "
                 "bounds-gpu (the same grid decides every cell's list on the GPU, no read-back; in core)")
            .widget(Kind::Combo, "queries")
            .choice<ChcrtQueries>(FIELD(chcrt.queries), {{"gl", ChcrtQueries::Gl},
                                                         {"batched", ChcrtQueries::Batched},
                                                         {"bounds-only", ChcrtQueries::BoundsOnly},
                                                         {"bounds-gpu", ChcrtQueries::BoundsGpu}}),
        Describe(Area::Chcrt, "--chcrt-bounds-cell", "chcrtBoundsCell",
                 "CHC+RT: ray bounds grid cell edge in pixels (a power of two)")
            .minusOneUnsets()
            .integer<int>(FIELD(chcrt.bounds.cellSize), 1),
        Describe(Area::Chcrt, "--chcrt-bounds-pieces", "chcrtBoundsPieces", "CHC+RT: ray bounds boxes per cell")
            .minusOneUnsets()
            .slider("bounds pieces", 1, 8)
            .integer<int>(FIELD(chcrt.bounds.pieces), 1),
        Describe(Area::Chcrt, "--chcrt-bounds-frustum", "chcrtBoundsFrustum",
                 "CHC+RT: also test each cell's ray interval (origins, directions, segment range) against a box")
            .checkbox("bounds frustum")
            .onOff(FIELD(chcrt.bounds.frustum)),
        Describe(Area::Chcrt, "--chcrt-camera-bounds", "chcrtCameraBounds",
                 "CHC+RT bounds-only: bound the renderer's primary rays from the camera instead of reducing them on the "
                 "GPU (no read-back)")
            .checkbox("camera ray bounds")
            .onOff(FIELD(chcrt.bounds.cameraRays)),
        Describe(Area::Chcrt, "--chcrt-cell-list-limit", "chcrtCellListLimit",
                 "CHC+RT bounds-only: cells with more subtrees traverse the whole BVH (0 = never)")
            .minusOneUnsets()
            .integer<uint32_t>(FIELD(chcrt.cellListLimit), 0),
        Describe(Area::Chcrt, "--chcrt-hints", "chcrtHints",
                 "CHC+RT bounds-only: test each ray's triangle of the previous frame first (hit hints)")
            .checkbox("hit hints")
            .onOff(FIELD(chcrt.hitHints)),
        Describe(Area::Chcrt, "--chcrt-closest-hints", "chcrtClosestHints",
                 "CHC+RT with hit hints: closest-hit rays (primary, diffuse) start from their previous hit's leaf too")
            .checkbox("closest-hit hints")
            .onOff(FIELD(chcrt.closestHitHints)),
        Describe(Area::Chcrt, "--chcrt-hint-pass", "chcrtHintPass",
                 "CHC+RT with hit hints: visit the hinted leaves in a pass of their own, then trace only the rays left "
                 "(compacted)")
            .checkbox("hint pass")
            .onOff(FIELD(chcrt.hintPass)),
        Describe(Area::Chcrt, "--chcrt-shared-shadow-lists", "chcrtSharedShadowLists",
                 "CHC+RT bounds-only: the shadow ray sets of one G-buffer share one ray bounds grid (surface points "
                 "swept to the light) and one set of cell lists")
            .checkbox("shared shadow lists")
            .onOff(FIELD(chcrt.shareShadowLists)),
        Describe(Area::Chcrt, "--chcrt-hemisphere-bounds", "chcrtHemisphereBounds",
                 "CHC+RT bounds-only: the AO ray sets of one G-buffer are bounded from one reduction of their surface "
                 "points and normals instead of a reduction per set")
            .checkbox("AO bounds from surface frames")
            .onOff(FIELD(chcrt.hemisphereBounds)),
        Describe(Area::Chcrt, "--chcrt-hint-pass-max-left", "chcrtHintPassMaxLeft",
                 "CHC+RT with the hint pass: a ray kind whose passes leave more than this share of the pixels to "
                 "trace twice in a row stops the pass, retrying every 16 traces")
            .defaults("0.25; out of core 0.5")
            .number(FIELD(chcrt.hintPassMaxLeft), 0.0, 1.0),
        Describe(Area::Chcrt, "--chcrt-pass-timer-interval", "",
                 "CHC+RT: time the passes (subtree_pass_ms, hint_pass_ms) on one trace in this many and estimate "
                 "them for all from those (1 = every trace, 0 = none)")
            .integer<uint32_t>(FIELD(chcrt.passTimerInterval), 0),
        Describe(Area::Chcrt, "--chcrt-hint-memory-mb", "",
                 "CHC+RT with hit hints: GPU memory for the hint images (4 bytes per ray per sample index and ray kind); "
                 "sample indices beyond it share images")
            .sets<uint64_t>(FIELD(chcrt.hintMemoryBytes), megabyteCodec()),
    };
}

// Line Spaces (linespace/README.md) and the N-tree of ntree+ls.
std::vector<Parameter> describeLineSpace() {
    return {
        Describe(Area::LineSpace, "--ls-n", "lsN", "Line Space patches per face edge N")
            .slider("N (patches per edge)", 1, 16)
            .integer<uint32_t>(FIELD(lineSpace.n), 1),
        Describe(Area::LineSpace, "--ls-depth", "lsDepth", "Line Space BVH depth D")
            .defaults("9; bvh+ls: 6 up to 1.5M triangles and one more per doubling above, at most 12")
            .slider("depth D", 1, 16)
            .integer<uint32_t>(FIELD(lineSpace.depth), 1),
        Describe(Area::LineSpace, "--ls-t", "lsT", "Line Space triangle threshold T")
            .slider("T", 1, 32)
            .integer<uint32_t>(FIELD(lineSpace.triangleThreshold), 1),
        Describe(Area::LineSpace, "--ls-angle", "lsAngle", "Candidate normal-angle threshold in degrees")
            .slider("candidate angle", 0, 90, "%.0f deg")
            .number(FIELD(lineSpaceTracing.candidateAngleDegrees), 0, 180),
        Describe(Area::LineSpaceModes, "--ls-modes", "lsModes",
                 "Line Space mode per ray type on top of the method's, e.g. primary=exact,shadow=shadow,ao=candidate,"
                 "diffuse=candidate,bounce=shadow,faces=front-start (modes: off, exact, shadow, candidate, "
                 "candidate-exact-start; faces: front-start, front, both)")
            .defaults("bvh+ls: diffuse=candidate, the others off; bvh+ls-exact: all exact, all off when more than "
                      "half the shafts are filled")
            .value("type=mode,...")
            .text(FIELD(lineSpaceTracing.modes), [](const std::string& text) { ls::LineSpaceModes{}.parse(text); }),
        Describe(Area::LineSpaceCache, "--ls-cache", "", "Line Space and N-tree cache directory (empty: no cache)")
            .text(FIELD(lineSpaceTracing.cacheDirectory)),
        Describe(Area::NTree, "--ls-ntree", "lsNtree", "N-tree with binary Line Spaces N:d for method ntree+ls")
            .value("N:d")
            .pairSliders("N-tree N", 2, 16, "N-tree depth d", 1, 8)
            .sets<ls::NTreeParams>(FIELD(ntree), formattedCodec<ls::NTreeParams>(ls::parseNTreeParams, [](const ls::NTreeParams& p) {
                                       return std::to_string(p.n) + ":" + std::to_string(p.depth);
                                   })),
        Describe(Area::NTree, "--ls-ntree-level", "lsNtreeLevel",
                 "ntree+ls: N-tree level whose occupied shafts count as occluded (as SS; >= d: exact)")
            .defaults("d - 1")
            .minusOneUnsets()
            .slider("shadow level (-1 = d-1)", -1, 8)
            .integer<uint32_t>(FIELD(ntreeShadow.shadowLevel), 0),
        Describe(Area::NTree, "--ls-ntree-near", "lsNtreeNear",
                 "ntree+ls: shadow-level nodes entered within this many node edges of the ray origin are handled like "
                 "the start node (0 = SS 4.1)")
            .slider("near (node edges)", 0, 8, "%.2f")
            .number(FIELD(ntreeShadow.nearEdges), 0, 1000),
        Describe(Area::NTree, "--ls-ntree-start", "lsNtreeStart",
                 "ntree+ls: the node a shadow ray starts or ends in: skip (SS 4.1) or exact (triangle tests)")
            .widget(Kind::Combo, "start node")
            .choice<bool>(FIELD(ntreeShadow.startExact), {{"skip", false}, {"exact", true}}),
    };
}

// Out of core (docs/outofcore.md): OutOfCoreOptions and the session's --out-of-core / --load-in-core.
std::vector<Parameter> describeOutOfCore() {
    return {
        Describe(Area::OutOfCore, "--out-of-core", "",
                 "Prepared scenes (.chs): chcrt methods trace through a GPU subtree cache fed from the file (CHC+RT "
                 "§5.4) instead of the in-core BVH")
            .flagWithoutValue()
            .emit(Emit::Always)
            .onOff(FIELD(outOfCoreScene.enabled)),
        Describe(Area::OutOfCore, "--gpu-cache-mb", "", "Out of core: GPU subtree cache budget in MiB")
            .emit(Emit::Always)
            .sets<uint64_t>(FIELD(outOfCore.gpuCacheBytes), megabyteCodec()),
        Describe(Area::OutOfCore, "--host-cache-mb", "", "Out of core: host subtree cache budget in MiB")
            .emit(Emit::Always)
            .sets<uint64_t>(FIELD(outOfCore.hostCacheBytes), megabyteCodec()),
        Describe(Area::OutOfCore, "--uploads-per-trace", "",
                 "Out of core: subtrees uploaded per trace at most; the rest waits for later frames (0 = no limit, "
                 "exact frames)")
            .defaults("0; the interactive viewer 16")
            .emit(Emit::Never)
            .integer<uint32_t>(FIELD(outOfCore.maxUploadsPerTrace), 0),
        Describe(Area::OutOfCore, "--prefetch-frames", "",
                 "Out of core: after each frame, read ahead into the host cache the subtrees in the view of this many "
                 "next frames of the walkthrough and those next to the visible ones (0 = no prefetch)")
            .emit(Emit::IfNotDefault)
            .integer<uint32_t>(FIELD(outOfCore.prefetchFrames), 0, 64),
        Describe(Area::OutOfCore, "--prefetch-mb", "",
                 "Out of core: at most this many MiB read ahead per frame (--prefetch-frames)")
            .emit(Emit::IfNotDefault)
            .sets<uint64_t>(FIELD(outOfCore.prefetchBytesPerFrame), megabyteCodec()),
        Describe(Area::OutOfCore, "--cache-policy", "", "Out of core: GPU cache replacement")
            .emit(Emit::IfNotDefault)
            .choice<outofcore::CachePolicy>(FIELD(outOfCore.policy), {{"round-robin", outofcore::CachePolicy::RoundRobin},
                                                                      {"lru", outofcore::CachePolicy::Lru}}),
        Describe(Area::OutOfCore, "--load-in-core", "",
                 "Out of core: also load the scene in core for pure-BVH references and id-indexed shading (auto: when "
                 "it takes less than a quarter of the RAM)")
            .emit(Emit::IfNotDefault)
            .choice<LoadInCore>(FIELD(outOfCoreScene.loadInCore),
                                {{"auto", LoadInCore::Auto}, {"on", LoadInCore::On}, {"off", LoadInCore::Off}}),
        // Issue #19: the projected-error threshold of the LOD proxies (docs/outofcore.md, "LOD proxies"); chcrt-lod's
        // default 1 pixel is set in app/methods.cpp, exact methods ignore it (they never trace proxies).
        Describe(Area::Lod, "--lod-pixels", "lodPixels",
                 "chcrt-lod: trace a subtree's LOD proxy where its geometric error projects below this many pixels "
                 "(> 0; approximate)")
            .defaults("1 (chcrt-lod)")
            .emit(Emit::IfGiven)
            .logSlider("LOD threshold (px)", 0.125f, 16.0f, "%.3g")
            .number(FIELD(outOfCore.lodPixels), 0.0, 1000.0),
    };
}

#undef FIELD

std::vector<Parameter> describeAll() {
    std::vector<Parameter> all;
    for (auto group : {describeSession, describeRender, describeBvh, describeChcrt, describeLineSpace, describeOutOfCore}) {
        for (Parameter& p : group()) all.push_back(std::move(p));
    }
    return all;
}

const CommonOptions& defaultOptions() {
    static const CommonOptions defaults;
    return defaults;
}

void unsetParameter(CommonOptions& o, const Parameter& p) {
    p.copy(defaultOptions(), o);
    o.given.erase(p.flag);
}

} // namespace

const char* toString(ParameterArea area) {
    switch (area) {
    case ParameterArea::Session: return "Scene, camera and output";
    case ParameterArea::Render: return "Image and sampling";
    case ParameterArea::Bvh: return "BVH";
    case ParameterArea::Chcrt: return "CHC+RT (chcrt methods)";
    case ParameterArea::ChcrtVisibility: return "CHC+RT approximate culling (chcrt-aggressive)";
    case ParameterArea::LineSpace: return "Line Space (bvh+ls, chcrt+ls methods)";
    case ParameterArea::LineSpaceModes: return "Line Space modes (bvh+ls, bvh+ls-exact)";
    case ParameterArea::NTree: return "N-tree (ntree+ls)";
    case ParameterArea::LineSpaceCache: return "Line Space and N-tree cache";
    case ParameterArea::OutOfCore: return "Out of core (prepared .chs scenes)";
    case ParameterArea::Lod: return "Level of detail (chcrt-lod)";
    }
    return "?";
}

bool isMethodArea(ParameterArea area) {
    return area == ParameterArea::Chcrt || area == ParameterArea::ChcrtVisibility || area == ParameterArea::LineSpace ||
           area == ParameterArea::LineSpaceModes || area == ParameterArea::NTree || area == ParameterArea::Lod;
}

const std::vector<Parameter>& parameterTable() {
    static const std::vector<Parameter> table = describeAll();
    return table;
}

const Parameter* findParameter(const std::string& flag) {
    for (const Parameter& p : parameterTable()) {
        if (p.flag == flag) return &p;
    }
    return nullptr;
}

const Parameter* findParameterByKey(const std::string& key) {
    if (key.empty()) return nullptr;
    for (const Parameter& p : parameterTable()) {
        if (p.key == key) return &p;
    }
    return nullptr;
}

void setParameter(CommonOptions& o, const Parameter& p, const std::string& text) {
    if (p.minusOneUnsets && text == "-1") return unsetParameter(o, p);
    p.parseText(o, text);
    o.given.insert(p.flag);
}

void setParameter(CommonOptions& o, const Parameter& p, const nlohmann::json& value) {
    if (value.is_null() || (p.minusOneUnsets && value.is_number_integer() && value.get<long long>() == -1)) {
        return unsetParameter(o, p);
    }
    p.parseJson(o, value);
    o.given.insert(p.flag);
}

void copyParameters(const CommonOptions& from, CommonOptions& to, const std::function<bool(const Parameter&)>& which) {
    for (const Parameter& p : parameterTable()) {
        if (!which(p)) continue;
        p.copy(from, to);
        if (from.isGiven(p.flag)) to.given.insert(p.flag);
        else to.given.erase(p.flag);
    }
}

std::string givenParameters(const CommonOptions& o, const std::function<bool(const Parameter&)>& which) {
    std::string out;
    for (const Parameter& p : parameterTable()) {
        if (which(p) && o.isGiven(p.flag)) out += (out.empty() ? "" : " ") + p.flag + "=" + p.text(o);
    }
    return out;
}

std::string commandLineArguments(const CommonOptions& o, const std::function<bool(ParameterArea)>& applies) {
    std::string line;
    for (const Parameter& p : parameterTable()) {
        if (p.emit == Emit::Never || !applies(p.area)) continue;
        const std::string value = p.text(o);
        if (p.emit == Emit::IfGiven && !o.isGiven(p.flag)) continue;
        if (p.emit == Emit::IfNotDefault && value == p.text(defaultOptions())) continue;
        if (p.isFlag) {
            if (p.json(o) == true) line += " " + p.flag;
            continue;
        }
        line += " " + p.flag + " " + shellWord(value);
    }
    return line;
}

std::string shellWord(const std::string& word) {
    const bool safe = !word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) ||
               std::string_view("-_./:,=+").find(c) != std::string_view::npos;
    });
    if (safe) return word;
    std::string quoted = "'";
    for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

std::string formatFloat(float value) {
    // The shortest text that reads back as the same float (9 significant digits always do).
    char text[32];
    for (int digits = 6; digits <= 9; ++digits) {
        std::snprintf(text, sizeof(text), "%.*g", digits, double(value));
        if (std::strtof(text, nullptr) == value) break;
    }
    return text;
}

} // namespace chcrt::app
