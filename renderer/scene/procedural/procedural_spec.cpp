// Parsing and printing of generator specs ("city:2m:seed=7").
#include "renderer/scene/procedural/procedural.h"

#include "renderer/core/error.h"

#include <charconv>
#include <cmath>
#include <string_view>

namespace chcrt {

namespace {

struct KindName {
    ProceduralKind kind;
    const char* name;
};
constexpr KindName kKindNames[] = {
    {ProceduralKind::City, "city"},
    {ProceduralKind::Interior, "interior"},
    {ProceduralKind::Plant, "plant"},
    {ProceduralKind::PlaneAndBox, "plane-and-box"},
    {ProceduralKind::ClosedBox, "closed-box"},
    {ProceduralKind::OneTriangle, "one-triangle"},
};

// Past ~1e9 triangles the 32-bit vertex indices (two vertices per triangle) would overflow.
constexpr double kMaxTriangles = 1e9;

// "\"" + std::string(x) trips GCC 12's -Wrestrict false positive (PR 105651), so quoting is spelled out.
std::string inQuotes(std::string_view text) {
    std::string result(1, '"');
    result.append(text);
    result += '"';
    return result;
}

[[noreturn]] void fail(const std::string& text, const std::string& why) {
    throw InputError("invalid scene generator spec " + inQuotes(text) + ": " + why);
}

// "1500000", "500k", "2m", "1.5m" -> triangles.
uint64_t parseCount(std::string_view token, const std::string& text) {
    double multiplier = 1.0;
    std::string_view digits = token;
    if (!digits.empty() && (digits.back() == 'k' || digits.back() == 'K')) multiplier = 1e3;
    if (!digits.empty() && (digits.back() == 'm' || digits.back() == 'M')) multiplier = 1e6;
    if (multiplier != 1.0) digits.remove_suffix(1);
    double value = 0.0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value,
                                              std::chars_format::fixed);
    if (digits.empty() || error != std::errc() || end != digits.data() + digits.size())
        fail(text, inQuotes(token) + " is not a triangle count (expected e.g. 500k, 2m or 1500000)");
    const double count = std::round(value * multiplier);
    if (!(count >= 1.0)) fail(text, "the triangle count must be at least 1");
    if (count > kMaxTriangles) fail(text, "the triangle count must be at most 1000m");
    return uint64_t(count);
}

uint32_t parseSeed(std::string_view value, const std::string& text) {
    uint32_t seed = 0;
    const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), seed);
    if (value.empty() || error != std::errc() || end != value.data() + value.size())
        fail(text, "seed " + inQuotes(value) + " is not an unsigned 32-bit integer");
    return seed;
}

bool isAnalytic(ProceduralKind kind) {
    return kind == ProceduralKind::PlaneAndBox || kind == ProceduralKind::ClosedBox ||
           kind == ProceduralKind::OneTriangle;
}

} // namespace

bool parseProceduralSpec(const std::string& text, ProceduralSpec& spec) {
    const std::string_view all(text);
    const size_t colon = all.find(':');
    const std::string_view head = all.substr(0, colon);
    const KindName* match = nullptr;
    for (const KindName& entry : kKindNames)
        if (head == entry.name) match = &entry;
    // Anything whose first field is not a generator name ("scenes/x.glb", "C:/x.gltf") is a file path.
    if (!match) return false;

    ProceduralSpec result;
    result.kind = match->kind;
    bool haveCount = false, haveSeed = false;
    size_t begin = colon;
    while (begin != std::string_view::npos) {
        const size_t next = all.find(':', begin + 1);
        const std::string_view field = all.substr(begin + 1, next == std::string_view::npos ? next : next - begin - 1);
        begin = next;
        if (field.empty()) fail(text, "empty field");
        const size_t equals = field.find('=');
        if (equals == std::string_view::npos) {
            if (haveCount) fail(text, "more than one triangle count");
            result.targetTriangles = parseCount(field, text);
            haveCount = true;
        } else if (field.substr(0, equals) == "seed") {
            if (haveSeed) fail(text, "more than one seed");
            result.seed = parseSeed(field.substr(equals + 1), text);
            haveSeed = true;
        } else {
            fail(text, "unknown option " + inQuotes(field.substr(0, equals)) + " (expected seed=N)");
        }
    }
    spec = result;
    return true;
}

std::string proceduralGeneratorNames() {
    std::string names;
    for (const KindName& entry : kKindNames) names += (names.empty() ? "" : ", ") + std::string(entry.name);
    return names;
}

std::string toString(const ProceduralSpec& spec) {
    std::string name;
    for (const KindName& entry : kKindNames)
        if (entry.kind == spec.kind) name = entry.name;
    // Analytic scenes ignore the count and the seed, so their canonical form is the bare name.
    if (isAnalytic(spec.kind)) return name;
    return name + ":" + std::to_string(spec.targetTriangles) + ":seed=" + std::to_string(spec.seed);
}

} // namespace chcrt
