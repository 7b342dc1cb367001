#include "app/viewer/viewer_script.h"

#include "renderer/core/error.h"
#include "renderer/render/render_settings.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace chcrt::app {
namespace {

struct StepParser {
    const std::string& file;
    size_t index;

    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(file + ": step " + std::to_string(index) + ": " + what);
    }
    template <typename T>
    T get(const nlohmann::json& value, const char* key) const {
        try {
            return value.get<T>();
        } catch (const nlohmann::json::exception&) {
            fail(std::string("'") + key + "' has the wrong type: " + value.dump());
        }
    }
    glm::vec3 vec3(const nlohmann::json& value, const char* key) const {
        const auto v = get<std::vector<float>>(value, key);
        if (v.size() != 3) fail(std::string("'") + key + "' must be [x, y, z]");
        return {v[0], v[1], v[2]};
    }
    void holdKey(WalkInput& input, const std::string& key) const {
        if (key == "W") input.forward = true;
        else if (key == "S") input.back = true;
        else if (key == "A") input.left = true;
        else if (key == "D") input.right = true;
        else if (key == "E") input.up = true;
        else if (key == "Q") input.down = true;
        else if (key == "SHIFT") input.fast = true;
        else fail("unknown key '" + key + "' (W, A, S, D, Q, E, SHIFT)");
    }

    ScriptStep parse(const nlohmann::json& j) const {
        if (!j.is_object()) fail("a step must be a JSON object");
        ScriptStep step;
        bool holdsInput = false;
        for (const auto& [key, value] : j.items()) {
            if (key == "frames") {
                step.frames = get<int>(value, "frames");
                if (step.frames < 0 || step.frames > 100000) fail("'frames' must be in [0, 100000]");
            } else if (key == "key") {
                holdKey(step.held, get<std::string>(value, "key"));
                holdsInput = true;
            } else if (key == "keys") {
                for (const std::string& k : get<std::vector<std::string>>(value, "keys")) holdKey(step.held, k);
                holdsInput = true;
            } else if (key == "mouse") {
                const auto v = get<std::vector<float>>(value, "mouse");
                if (v.size() != 2) fail("'mouse' must be [dx, dy]");
                step.held.lookPixels = {v[0], v[1]};
                holdsInput = true;
            } else if (key == "scroll") {
                step.scrollSteps = get<float>(value, "scroll");
            } else if (key == "set") {
                if (!value.is_object()) fail("'set' must be an object of settings");
                step.set = value;
            } else if (key == "camera") {
                if (!value.is_object() || !value.contains("eye") || !value.contains("target")) {
                    fail("'camera' needs \"eye\" and \"target\"");
                }
                Camera c;
                c.eye = vec3(value["eye"], "eye");
                c.target = vec3(value["target"], "target");
                if (value.contains("fov")) c.fovYDegrees = get<float>(value["fov"], "fov");
                if (c.eye == c.target) fail("camera eye and target must differ");
                step.camera = c;
            } else if (key == "pathFrame") {
                step.pathFrame = get<int>(value, "pathFrame");
                if (*step.pathFrame < 0) fail("'pathFrame' must be >= 0");
            } else if (key == "play") {
                step.play = get<bool>(value, "play");
            } else if (key == "action") {
                step.action = get<std::string>(value, "action");
                if (step.action != "reset" && step.action != "frameScene" && step.action != "copyCommandLine" &&
                    step.action != "recordStart") {
                    fail("unknown action '" + step.action + "' (reset, frameScene, copyCommandLine, recordStart)");
                }
            } else if (key == "press") {
                const auto name = get<std::string>(value, "press");
                bool known = false;
                for (const char* k : kPressableKeys) known |= name == k;
                if (!known) fail("cannot press '" + name + "' (R, F, P, V, C, F9, F12, +, -, TAB)");
                step.presses.push_back(name);
            } else if (key == "pick") {
                const auto v = get<std::vector<int>>(value, "pick");
                if (v.size() != 2 || v[0] < 0 || v[1] < 0) fail("'pick' must be [x, y], pixels of the internal image");
                step.pick = std::make_pair(v[0], v[1]);
            } else if (key == "recordStop") {
                step.recordStop = get<std::string>(value, "recordStop");
            } else if (key == "resize") {
                const auto v = get<std::vector<int>>(value, "resize");
                if (v.size() != 2 || v[0] < 1 || v[1] < 1) fail("'resize' must be [width, height], both >= 1");
                step.resize = std::make_pair(v[0], v[1]);
            } else if (key == "loadScene") {
                step.loadScene = get<std::string>(value, "loadScene");
            } else if (key == "screenshot") {
                step.screenshot = get<std::string>(value, "screenshot");
            } else if (key == "windowScreenshot") {
                step.windowScreenshot = get<std::string>(value, "windowScreenshot");
            } else if (key == "expect") {
                if (!value.is_object()) fail("'expect' must be an object");
                step.expect = value;
            } else {
                fail("unknown key '" + key + "'");
            }
        }
        // Input without a frame count is held for one frame: it would otherwise do nothing.
        if (holdsInput && !j.contains("frames")) step.frames = 1;
        return step;
    }
};

} // namespace

std::vector<ScriptStep> parseViewerScript(const std::string& jsonText, const std::string& nameForErrors) {
    nlohmann::json root;
    try {
        root = nlohmann::json::parse(jsonText);
    } catch (const nlohmann::json::parse_error& e) {
        throw InputError(nameForErrors + ": malformed JSON: " + e.what());
    }
    if (!root.is_array()) throw InputError(nameForErrors + ": a viewer script is a JSON list of steps");
    std::vector<ScriptStep> steps;
    for (size_t i = 0; i < root.size(); ++i) steps.push_back(StepParser{nameForErrors, i}.parse(root[i]));
    return steps;
}

std::vector<ScriptStep> loadViewerScript(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw InputError("cannot read viewer script " + file.string());
    std::stringstream text;
    text << in.rdbuf();
    return parseViewerScript(text.str(), file.string());
}

std::vector<std::string> unmetExpectations(const nlohmann::json& expect, const ScriptObservation& seen) {
    std::vector<std::string> unmet;
    const auto check = [&](bool met, const std::string& what) {
        if (!met) unmet.push_back(what);
    };
    const auto flag = [](bool value) { return std::string(value ? "true" : "false"); };
    for (const auto& [key, value] : expect.items()) {
        if (key == "cappedRays") {
            check(seen.cappedRays == value.get<uint64_t>(), "cappedRays = " + std::to_string(seen.cappedRays));
        } else if (key == "minRaysGenerated") {
            check(seen.raysGenerated >= value.get<uint64_t>(), "raysGenerated = " + std::to_string(seen.raysGenerated));
        } else if (key == "tracePasses") {
            for (const auto& [type, passes] : value.items()) {
                const uint64_t actual = seen.tracePasses[size_t(parseRayType(type))];
                check(actual == passes.get<uint64_t>(), type + " passes = " + std::to_string(actual));
            }
        } else if (key == "accumulatedFrames") {
            check(seen.accumulatedFrames == value.get<int>(), "accumulatedFrames = " + std::to_string(seen.accumulatedFrames));
        } else if (key == "imageSize") {
            const auto size = value.get<std::vector<int>>();
            check(size.size() == 2 && size[0] == seen.width && size[1] == seen.height,
                  "imageSize = " + std::to_string(seen.width) + "x" + std::to_string(seen.height));
        } else if (key == "method") {
            check(seen.method == value.get<std::string>(), "method = " + seen.method);
        } else if (key == "primary") {
            check(seen.primary == value.get<std::string>(), "primary = " + seen.primary);
        } else if (key == "viewMode") {
            check(seen.viewMode == value.get<std::string>(), "viewMode = " + seen.viewMode);
        } else if (key == "playing") {
            check(seen.playing == value.get<bool>(), "playing = " + flag(seen.playing));
        } else if (key == "scene") {
            check(seen.scene == value.get<std::string>(), "scene = " + seen.scene);
        } else if (key == "pathFrame") {
            check(seen.pathFrame == value.get<int>(), "pathFrame = " + std::to_string(seen.pathFrame));
        } else if (key == "shaftNodePicked") {
            check(seen.shaftNodePicked == value.get<bool>(), "shaftNodePicked = " + flag(seen.shaftNodePicked));
        } else if (key == "outOfCore") {
            check(seen.outOfCore == value.get<bool>(), "outOfCore = " + flag(seen.outOfCore));
        } else if (key == "loadProgress") {
            check(std::abs(seen.loadProgress - value.get<double>()) <= 1e-9, "loadProgress = " + std::to_string(seen.loadProgress));
        } else if (key == "failedFrames") {
            check(seen.failedFrames == value.get<int>(), "failedFrames = " + std::to_string(seen.failedFrames));
        } else if (key == "frameFailed") {
            check(seen.frameFailed == value.get<bool>(), "frameFailed = " + flag(seen.frameFailed));
        } else {
            throw InputError("script: unknown expectation '" + key + "'");
        }
    }
    return unmet;
}

ScriptRunner::Advance ScriptRunner::advance(const std::function<void(const ScriptStep&)>& actions,
                                            const std::function<void(const ScriptStep&)>& checks,
                                            const std::function<bool()>& waiting) {
    while (framesLeft_ == 0) {
        if (current_) { // the step's frames are done: its checks see their result
            checks(*current_);
            current_ = nullptr;
        }
        if (next_ >= steps_.size() || failures_ > 0) return Advance::Ended;
        current_ = &steps_[next_++];
        actions(*current_);
        framesLeft_ = current_->frames;
        if (waiting()) return Advance::Waiting;
    }
    --framesLeft_;
    ++frame_;
    return Advance::Frame;
}

size_t ScriptRunner::totalFrames() const {
    size_t total = 0;
    for (const ScriptStep& s : steps_) total += size_t(std::max(s.frames, 0));
    return total;
}

} // namespace chcrt::app
