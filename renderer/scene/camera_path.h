#pragma once
// Camera paths (walkthroughs): JSON files of the form
//   {"version": 1, "fps": 30, "fovY": 60,
//    "keyframes": [{"t": 0.0, "eye": [x,y,z], "target": [x,y,z], "up": [0,1,0]}, ...]}
// Frame k is at time k / fps. Between keyframes, eye and target follow a centripetal Catmull-Rom spline
// through the keyframe positions (so paths pass through every keyframe without overshoot), up is linearly
// interpolated and renormalised; before the first / after the last keyframe the camera is clamped.
#include "renderer/scene/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace chcrt {

struct CameraKeyframe {
    double t = 0.0; // seconds, strictly increasing along the path
    glm::vec3 eye{0.0f};
    glm::vec3 target{0.0f, 0.0f, -1.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
};

struct CameraPath {
    std::string name; // file stem or generator name
    double fps = 30.0;
    float fovYDegrees = 60.0f;
    std::vector<CameraKeyframe> keyframes; // at least one

    double duration() const { return keyframes.empty() ? 0.0 : keyframes.back().t - keyframes.front().t; }
    // Number of frames covering [first keyframe t, last keyframe t] at fps (at least 1).
    int frameCount() const;
    // The camera at time seconds (clamped to the path).
    Camera cameraAt(double seconds) const;
    Camera cameraAtFrame(int frame) const { return cameraAt(keyframes.front().t + frame / fps); }
};

// Parsing throws InputError with the file name and what is wrong (malformed JSON, missing fields, version,
// non-increasing t, non-finite numbers, eye == target).
CameraPath parseCameraPath(const std::string& jsonText, const std::string& nameForErrors);
CameraPath loadCameraPath(const std::filesystem::path& file);
std::string cameraPathToJson(const CameraPath& path);
// Writes atomically (temp file + rename).
void saveCameraPath(const CameraPath& path, const std::filesystem::path& file);

// A one-keyframe path holding a single camera.
CameraPath singleCameraPath(const Camera& camera, const std::string& name);

} // namespace chcrt
