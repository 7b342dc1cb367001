#pragma once
// Camera paths (walkthroughs): JSON files of the form
//   {"version": 1, "fps": 30, "fovY": 60,
//    "keyframes": [{"t": 0.0, "eye": [x,y,z], "target": [x,y,z], "up": [0,1,0]}, ...]}
// "fps" (default 30) and "fovY" (degrees, default 60) are optional, as is each keyframe's "up" (default
// [0,1,0]); unknown fields are errors. Frame k is at time t0 + k / fps.
//
// Interpolation: between keyframes, eye and target each follow a centripetal Catmull-Rom spline (alpha = 1/2,
// Barry-Goldman evaluation) through the keyframe positions, so paths pass exactly through every keyframe
// without cusps or overshooting loops. Within segment [t_i, t_{i+1}] the spline parameter is linear in time,
// so unevenly spaced keyframe times are respected. A missing neighbour at either end of the path (or one at
// the same position) is replaced by reflecting the segment (P_{-1} = 2 P_0 - P_1), so two keyframes give a
// straight line; an eye (or target) that is the same at both ends of a segment stays still. up is linearly
// interpolated and renormalised, fovY is constant; before the first / after the last keyframe the camera is
// clamped to it.
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

// The most frames a walkthrough may have (about 92 hours at 30 fps): reading refuses longer ones, whose frame
// lists (`--frames all`) could not be allocated.
inline constexpr int kMaxCameraPathFrames = 10'000'000;

struct CameraPath {
    std::string name; // file stem or generator name
    double fps = 30.0;
    float fovYDegrees = 60.0f;
    std::vector<CameraKeyframe> keyframes; // at least one

    double duration() const { return keyframes.empty() ? 0.0 : keyframes.back().t - keyframes.front().t; }
    // Number of frames covering [first keyframe t, last keyframe t] at fps: floor(duration * fps) + 1.
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
