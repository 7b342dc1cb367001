#include "renderer/scene/camera_path.h"

#include "renderer/core/error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string_view>

namespace chcrt {

namespace fs = std::filesystem;

namespace {

using nlohmann::json;

// "\"" + std::string(x) trips GCC 12's -Wrestrict false positive (PR 105651), so quoting is spelled out.
std::string inQuotes(std::string_view text) {
    std::string result(1, '"');
    result.append(text);
    result += '"';
    return result;
}

// Reads and checks a camera path document; every failure names the file, the keyframe and the field.
class CameraPathParser {
public:
    explicit CameraPathParser(const std::string& name) : name_(name) {}

    CameraPath parse(const std::string& text) const {
        json root;
        try {
            root = json::parse(text);
        } catch (const json::exception& e) { // parse_error, or out_of_range for overflowing numbers (1e999)
            fail("", std::string("malformed JSON: ") + withoutJsonPrefix(e.what()));
        }
        if (!root.is_object()) {
            fail("", "the top level must be a JSON object");
        }
        checkKeys(root, "", {"version", "fps", "fovY", "keyframes"});

        CameraPath path;
        path.name = fs::path(name_).stem().string();
        if (!root.contains("version")) {
            fail("", "missing \"version\" (expected 1)");
        }
        if (!root["version"].is_number() || root["version"].get<double>() != 1.0) {
            fail("", "unsupported \"version\" " + root["version"].dump() + " (expected 1)");
        }
        if (root.contains("fps")) {
            path.fps = number(root["fps"], "", "fps");
            if (!(path.fps > 0.0)) {
                fail("", "\"fps\" must be greater than 0");
            }
        }
        if (root.contains("fovY")) {
            const double fov = number(root["fovY"], "", "fovY");
            if (!(fov > 0.0 && fov < 180.0)) {
                fail("", "\"fovY\" must be between 0 and 180 degrees (exclusive)");
            }
            path.fovYDegrees = float(fov);
        }
        if (!root.contains("keyframes") || !root["keyframes"].is_array() || root["keyframes"].empty()) {
            fail("", "\"keyframes\" must be a non-empty array");
        }
        const json& keyframes = root["keyframes"];
        for (size_t i = 0; i < keyframes.size(); ++i) {
            path.keyframes.push_back(parseKeyframe(keyframes[i], "keyframe " + std::to_string(i) + ": "));
            if (i > 0 && !(path.keyframes[i].t > path.keyframes[i - 1].t)) {
                std::ostringstream why;
                why << "\"t\" = " << path.keyframes[i].t << " is not greater than keyframe " << i - 1
                    << "'s \"t\" = " << path.keyframes[i - 1].t << " (times must strictly increase)";
                fail("keyframe " + std::to_string(i) + ": ", why.str());
            }
        }
        const double frames = std::floor(path.duration() * path.fps) + 1.0;
        if (!(frames <= double(kMaxCameraPathFrames))) {
            std::ostringstream why;
            why << path.duration() << " s at " << path.fps << " fps is " << frames << " frames, more than the "
                << kMaxCameraPathFrames << " a walkthrough may have (lower \"fps\")";
            fail("", why.str());
        }
        return path;
    }

private:
    [[noreturn]] void fail(const std::string& where, const std::string& why) const {
        throw InputError(name_ + ": " + where + why);
    }

    static std::string withoutJsonPrefix(const std::string& message) {
        // nlohmann's "[json.exception.parse_error.101] parse error at line 1, column 5: ..." -> "parse error ..."
        const size_t bracket = message.find("] ");
        return bracket == std::string::npos ? message : message.substr(bracket + 2);
    }

    void checkKeys(const json& object, const std::string& where, std::initializer_list<const char*> known) const {
        for (const auto& item : object.items()) {
            if (std::none_of(known.begin(), known.end(), [&](const char* k) { return item.key() == k; })) {
                std::string list;
                for (const char* k : known) {
                    list += (list.empty() ? "" : ", ") + inQuotes(k);
                }
                fail(where, "unknown field " + inQuotes(item.key()) + " (expected " + list + ")");
            }
        }
    }

    double number(const json& value, const std::string& where, const char* field) const {
        // JSON has no NaN/Inf literals and nlohmann rejects overflowing ones (1e999) while parsing; checked
        // anyway so that the contract does not hang on that detail.
        if (!value.is_number() || !std::isfinite(value.get<double>())) {
            fail(where, inQuotes(field) + " must be a finite number, not " + value.dump());
        }
        return value.get<double>();
    }

    glm::vec3 vector3(const json& value, const std::string& where, const char* field) const {
        bool valid = value.is_array() && value.size() == 3;
        glm::vec3 v(0.0f);
        for (size_t k = 0; valid && k < 3; ++k) {
            valid = value[k].is_number() && std::isfinite(float(value[k].get<double>()));
            v[int(k)] = valid ? float(value[k].get<double>()) : 0.0f;
        }
        if (!valid) {
            fail(where, inQuotes(field) + " must be an array of 3 finite numbers, not " + value.dump());
        }
        return v;
    }

    CameraKeyframe parseKeyframe(const json& value, const std::string& where) const {
        if (!value.is_object()) {
            fail(where, "must be an object with \"t\", \"eye\", \"target\" and optionally \"up\"");
        }
        checkKeys(value, where, {"t", "eye", "target", "up"});
        for (const char* field : {"t", "eye", "target"}) {
            if (!value.contains(field)) {
                fail(where, "missing " + inQuotes(field));
            }
        }
        CameraKeyframe keyframe;
        keyframe.t = number(value["t"], where, "t");
        keyframe.eye = vector3(value["eye"], where, "eye");
        keyframe.target = vector3(value["target"], where, "target");
        if (value.contains("up")) {
            keyframe.up = vector3(value["up"], where, "up");
        }
        if (keyframe.eye == keyframe.target) {
            fail(where, "\"eye\" and \"target\" are the same point (no view direction)");
        }
        const glm::dvec3 view = glm::normalize(glm::dvec3(keyframe.target) - glm::dvec3(keyframe.eye));
        const double upLength = glm::length(glm::dvec3(keyframe.up));
        if (upLength == 0.0 || glm::length(glm::cross(view, glm::dvec3(keyframe.up) / upLength)) < 1e-6) {
            fail(where, "\"up\" is zero or parallel to the view direction (target - eye)");
        }
        return keyframe;
    }

    const std::string& name_;
};

// Centripetal Catmull-Rom (alpha = 1/2; Yuksel, Schaefer, Keyser 2011: no cusps or self-intersections within a
// segment) between p1 and p2 at s in [0, 1], evaluated with the Barry-Goldman pyramid. s maps linearly onto the
// knot interval [k1, k2], which is what makes the spline parameter piecewise linear in time.
glm::dvec3 centripetalCatmullRom(glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, glm::dvec3 p3, double s) {
    if (p1 == p2) {
        return p1; // a camera that rests between two keyframes stays put instead of looping
    }
    // A missing or coincident neighbour would make a zero knot interval; reflecting the segment gives the
    // natural end tangent instead (for two keyframes the result is the straight line).
    if (p0 == p1) {
        p0 = 2.0 * p1 - p2;
    }
    if (p3 == p2) {
        p3 = 2.0 * p2 - p1;
    }
    const double k0 = 0.0;
    const double k1 = k0 + std::sqrt(glm::length(p1 - p0));
    const double k2 = k1 + std::sqrt(glm::length(p2 - p1));
    const double k3 = k2 + std::sqrt(glm::length(p3 - p2));
    const double k = k1 + s * (k2 - k1);
    const auto lerp = [k](const glm::dvec3& a, const glm::dvec3& b, double ka, double kb) {
        return a + (b - a) * ((k - ka) / (kb - ka));
    };
    const glm::dvec3 a1 = lerp(p0, p1, k0, k1);
    const glm::dvec3 a2 = lerp(p1, p2, k1, k2);
    const glm::dvec3 a3 = lerp(p2, p3, k2, k3);
    const glm::dvec3 b1 = lerp(a1, a2, k0, k2);
    const glm::dvec3 b2 = lerp(a2, a3, k1, k3);
    return lerp(b1, b2, k1, k2);
}

// The spline through one attribute (eye or target) of all keyframes, on segment i at s in (0, 1).
glm::vec3 splineAt(const std::vector<CameraKeyframe>& keys, glm::vec3 CameraKeyframe::*field, size_t i, double s) {
    const size_t n = keys.size();
    const glm::dvec3 p1(keys[i].*field);
    const glm::dvec3 p2(keys[i + 1].*field);
    const glm::dvec3 p0 = i > 0 ? glm::dvec3(keys[i - 1].*field) : p1; // reflected above
    const glm::dvec3 p3 = i + 2 < n ? glm::dvec3(keys[i + 2].*field) : p2; // reflected above
    return glm::vec3(centripetalCatmullRom(p0, p1, p2, p3, s));
}

glm::vec3 normalizedOr(const glm::vec3& v, const glm::vec3& fallback) {
    const float length = glm::length(v);
    return length > 1e-6f ? v / length : fallback;
}

// Shortest decimal text that reads back as the same float, as a double, so the JSON says 0.3 and not
// 0.30000001192092896.
double shortestDouble(float value) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, value);
    double shortest = value;
    std::from_chars(text, result.ptr, shortest);
    return shortest;
}

json vectorJson(const glm::vec3& v) {
    return json::array({shortestDouble(v.x), shortestDouble(v.y), shortestDouble(v.z)});
}

} // namespace

int CameraPath::frameCount() const {
    // The epsilon keeps e.g. 2.9999999996 frames (0.1 s steps) from losing the last frame.
    const double frames = std::floor(duration() * fps + 1e-9) + 1.0;
    return frames >= double(INT_MAX) ? INT_MAX : std::max(1, int(frames));
}

Camera CameraPath::cameraAt(double seconds) const {
    Camera camera;
    camera.fovYDegrees = fovYDegrees;
    if (keyframes.empty()) {
        return camera;
    }
    // Clamp outside [t0, tN] (NaN counts as before the start).
    const CameraKeyframe* fixed = nullptr;
    if (!(seconds > keyframes.front().t)) {
        fixed = &keyframes.front();
    } else if (seconds >= keyframes.back().t) {
        fixed = &keyframes.back();
    }
    if (fixed) {
        camera.eye = fixed->eye;
        camera.target = fixed->target;
        camera.up = normalizedOr(fixed->up, glm::vec3(0.0f, 1.0f, 0.0f));
        return camera;
    }
    // Segment i with t_i <= seconds < t_{i+1}; keyframes hit exactly because s = 0 returns keyframe i.
    const auto next = std::upper_bound(keyframes.begin(), keyframes.end(), seconds,
                                       [](double time, const CameraKeyframe& k) { return time < k.t; });
    const size_t i = size_t(next - keyframes.begin()) - 1;
    const CameraKeyframe& a = keyframes[i];
    const CameraKeyframe& b = keyframes[i + 1];
    const double s = (seconds - a.t) / (b.t - a.t);
    const glm::vec3 upA = normalizedOr(a.up, glm::vec3(0.0f, 1.0f, 0.0f));
    if (s == 0.0) {
        camera.eye = a.eye;
        camera.target = a.target;
        camera.up = upA;
        return camera;
    }
    camera.eye = splineAt(keyframes, &CameraKeyframe::eye, i, s);
    camera.target = splineAt(keyframes, &CameraKeyframe::target, i, s);
    const glm::vec3 upB = normalizedOr(b.up, glm::vec3(0.0f, 1.0f, 0.0f));
    camera.up = normalizedOr(upA + float(s) * (upB - upA), upA); // opposite ups: keep the first
    return camera;
}

CameraPath parseCameraPath(const std::string& jsonText, const std::string& nameForErrors) {
    return CameraPathParser(nameForErrors).parse(jsonText);
}

CameraPath loadCameraPath(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        throw InputError(file.string() + ": cannot open camera path file");
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) {
        throw InputError(file.string() + ": cannot read camera path file");
    }
    CameraPath path = parseCameraPath(text.str(), file.string());
    path.name = file.stem().string();
    return path;
}

std::string cameraPathToJson(const CameraPath& path) {
    nlohmann::ordered_json root;
    root["version"] = 1;
    root["fps"] = path.fps;
    root["fovY"] = shortestDouble(path.fovYDegrees);
    root["keyframes"] = nlohmann::ordered_json::array();
    for (const CameraKeyframe& keyframe : path.keyframes) {
        nlohmann::ordered_json k;
        k["t"] = keyframe.t;
        k["eye"] = vectorJson(keyframe.eye);
        k["target"] = vectorJson(keyframe.target);
        k["up"] = vectorJson(keyframe.up);
        root["keyframes"].push_back(std::move(k));
    }
    return root.dump(2) + "\n";
}

void saveCameraPath(const CameraPath& path, const fs::path& file) {
    const std::string text = cameraPathToJson(path);
    fs::path temp = file;
    temp.replace_filename(file.filename().string() + ".tmp"); // same directory, so the rename is atomic
    std::error_code ec;
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        out << text;
        out.close();
        if (!out) {
            fs::remove(temp, ec);
            throw InputError(file.string() + ": cannot write camera path file");
        }
    }
    fs::rename(temp, file, ec);
    if (ec) {
        const std::string reason = ec.message();
        fs::remove(temp, ec);
        throw InputError(file.string() + ": cannot write camera path file (" + reason + ")");
    }
}

CameraPath singleCameraPath(const Camera& camera, const std::string& name) {
    CameraPath path;
    path.name = name;
    path.fovYDegrees = camera.fovYDegrees;
    CameraKeyframe keyframe;
    keyframe.t = 0.0;
    keyframe.eye = camera.eye;
    keyframe.target = camera.target;
    keyframe.up = camera.up;
    path.keyframes.push_back(keyframe);
    return path;
}

} // namespace chcrt
