#include "renderer/core/error.h"
#include "renderer/scene/camera_path.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <fstream>

namespace chcrt {
namespace {

namespace fs = std::filesystem;

const char* kValidPath = R"({
  "version": 1, "fps": 24, "fovY": 45,
  "keyframes": [
    {"t": 0.0, "eye": [0, 1, 10], "target": [0, 0, 0]},
    {"t": 1.0, "eye": [10, 2, 0], "target": [0, 0.5, 0], "up": [0, 2, 0]},
    {"t": 4.0, "eye": [0, 3, -10], "target": [1, 0, 0]},
    {"t": 4.5, "eye": [-10, 1, 0], "target": [0, 0, 1], "up": [0.1, 1, 0]}
  ]
})";

void expectVecEq(const glm::vec3& a, const glm::vec3& b) {
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.z, b.z);
}

TEST(CameraPath, ParsesValidFile) {
    const CameraPath path = parseCameraPath(kValidPath, "walks/walk.json");
    EXPECT_EQ(path.name, "walk");
    EXPECT_EQ(path.fps, 24.0);
    EXPECT_EQ(path.fovYDegrees, 45.0f);
    ASSERT_EQ(path.keyframes.size(), 4u);
    EXPECT_EQ(path.keyframes[2].t, 4.0);
    expectVecEq(path.keyframes[1].eye, {10, 2, 0});
    expectVecEq(path.keyframes[1].target, {0, 0.5f, 0});
    expectVecEq(path.keyframes[1].up, {0, 2, 0});
    expectVecEq(path.keyframes[0].up, {0, 1, 0}); // default
    EXPECT_DOUBLE_EQ(path.duration(), 4.5);
    EXPECT_EQ(path.frameCount(), 109); // floor(4.5 * 24) + 1
}

TEST(CameraPath, Defaults) {
    const CameraPath path =
        parseCameraPath(R"({"version": 1, "keyframes": [{"t": 2, "eye": [0,0,1], "target": [0,0,0]}]})", "p");
    EXPECT_EQ(path.fps, 30.0);
    EXPECT_EQ(path.fovYDegrees, 60.0f);
    EXPECT_EQ(path.frameCount(), 1);
    const Camera camera = path.cameraAtFrame(0);
    expectVecEq(camera.eye, {0, 0, 1});
    EXPECT_EQ(camera.fovYDegrees, 60.0f);
}

struct BadCase {
    const char* json;
    const char* expected; // must appear in the message
};

TEST(CameraPath, MalformedInputThrowsUsefulMessages) {
    const std::string ok = R"("eye": [0,0,1], "target": [0,0,0])";
    const auto one = [&](const std::string& keyframe) {
        return R"({"version": 1, "keyframes": [)" + keyframe + "]}";
    };
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"{", "malformed JSON"},
        {R"({"version": 1,})", "malformed JSON"},
        {"[]", "top level must be a JSON object"},
        {R"({"keyframes": [{"t": 0, )" + ok + "}]}", "missing \"version\""},
        {R"({"version": 2, "keyframes": [{"t": 0, )" + ok + "}]}", "unsupported \"version\" 2"},
        {R"({"version": "1", "keyframes": [{"t": 0, )" + ok + "}]}", "unsupported \"version\""},
        {R"({"version": 1})", "\"keyframes\" must be a non-empty array"},
        {R"({"version": 1, "keyframes": []})", "\"keyframes\" must be a non-empty array"},
        {R"({"version": 1, "keyframes": {}})", "\"keyframes\" must be a non-empty array"},
        {R"({"version": 1, "fps": 0, "keyframes": [{"t": 0, )" + ok + "}]}", "\"fps\" must be greater than 0"},
        {R"({"version": 1, "fps": "30", "keyframes": [{"t": 0, )" + ok + "}]}", "\"fps\" must be a finite number"},
        {R"({"version": 1, "fovY": 180, "keyframes": [{"t": 0, )" + ok + "}]}", "\"fovY\" must be between"},
        {R"({"version": 1, "fovY": 0, "keyframes": [{"t": 0, )" + ok + "}]}", "\"fovY\" must be between"},
        {R"({"version": 1, "speed": 2, "keyframes": [{"t": 0, )" + ok + "}]}", "unknown field \"speed\""},
        {one("[0, 1]"), "keyframe 0: must be an object"},
        {one(R"({)" + ok + "}"), "keyframe 0: missing \"t\""},
        {one(R"({"t": 0, "eye": [0,0,1]})"), "keyframe 0: missing \"target\""},
        {one(R"({"t": "0", )" + ok + "}"), "keyframe 0: \"t\" must be a finite number"},
        // JSON has no NaN or Inf; the nearest thing, an overflowing literal, is rejected by the parser.
        {one(R"({"t": 1e999, )" + ok + "}"), "malformed JSON: number overflow parsing '1e999'"},
        {one(R"({"t": 0, "eye": [-1e999, 0, 1], "target": [0,0,0]})"), "malformed JSON: number overflow"},
        {one(R"({"t": 0, "eye": [0, 0, 1], "target": [1e39,0,0]})"), "keyframe 0: \"target\" must be an array of 3"},
        {one(R"({"t": 0, "eye": [0, 1], "target": [0,0,0]})"), "keyframe 0: \"eye\" must be an array of 3"},
        {one(R"({"t": 0, "eye": [0, 0, "1"], "target": [0,0,0]})"), "keyframe 0: \"eye\" must be an array of 3"},
        {one(R"({"t": 0, "eye": [1, 2, 3], "target": [1, 2, 3]})"), "keyframe 0: \"eye\" and \"target\" are the same"},
        {one(R"({"t": 0, )" + ok + R"(, "up": [0, 0, -3]})"), "keyframe 0: \"up\" is zero or parallel"},
        {one(R"({"t": 0, )" + ok + R"(, "up": [0, 0, 0]})"), "keyframe 0: \"up\" is zero or parallel"},
        {one(R"({"t": 0, )" + ok + R"(, "fov": 3})"), "keyframe 0: unknown field \"fov\""},
        {one(R"({"t": 0, )" + ok + R"(}, {"t": 1, )" + ok + R"(}, {"t": 1, )" + ok + "}"),
         "keyframe 2: \"t\" = 1 is not greater than keyframe 1's \"t\" = 1"},
        {one(R"({"t": 5, )" + ok + R"(}, {"t": 1, )" + ok + "}"), "keyframe 1: \"t\" = 1 is not greater"},
        {one(R"({"t": 0, )" + ok + R"(}, {"t": 1, "eye": [0,0,1]})"), "keyframe 1: missing \"target\""},
    };
    for (const auto& [text, expected] : cases) {
        try {
            parseCameraPath(text, "walk.json");
            ADD_FAILURE() << "no error for " << text;
        } catch (const InputError& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind("walk.json: ", 0), 0u) << message;
            EXPECT_NE(message.find(expected), std::string::npos) << "expected \"" << expected << "\" in: " << message;
        }
    }
}

TEST(CameraPath, PassesThroughKeyframesExactly) {
    const CameraPath path = parseCameraPath(kValidPath, "walk");
    for (const CameraKeyframe& keyframe : path.keyframes) {
        const Camera camera = path.cameraAt(keyframe.t);
        expectVecEq(camera.eye, keyframe.eye);
        expectVecEq(camera.target, keyframe.target);
        const glm::vec3 up = glm::normalize(keyframe.up);
        EXPECT_NEAR(glm::length(camera.up - up), 0.0f, 1e-6f);
        EXPECT_EQ(camera.fovYDegrees, 45.0f);
    }
}

TEST(CameraPath, IsContinuous) {
    const CameraPath path = parseCameraPath(kValidPath, "walk");
    // Steps of 1e-4 s; the fastest segment moves ~15 units in 0.5 s, so a step moves well under 0.01.
    Camera previous = path.cameraAt(-0.001);
    float largestStep = 0.0f;
    for (double t = -0.001; t <= 4.501; t += 1e-4) {
        const Camera camera = path.cameraAt(t);
        largestStep = std::max({largestStep, glm::length(camera.eye - previous.eye),
                                glm::length(camera.target - previous.target), glm::length(camera.up - previous.up)});
        previous = camera;
    }
    EXPECT_LT(largestStep, 0.01f);
    EXPECT_GT(largestStep, 0.0f);
    // Approaching a keyframe from below converges to it.
    for (const CameraKeyframe& keyframe : path.keyframes) {
        EXPECT_LT(glm::length(path.cameraAt(keyframe.t - 1e-7).eye - keyframe.eye), 1e-4f);
    }
}

TEST(CameraPath, ClampsOutsideTheKeyframes) {
    const CameraPath path = parseCameraPath(kValidPath, "walk");
    expectVecEq(path.cameraAt(-100.0).eye, path.keyframes.front().eye);
    expectVecEq(path.cameraAt(100.0).eye, path.keyframes.back().eye);
    expectVecEq(path.cameraAt(100.0).target, path.keyframes.back().target);
    expectVecEq(path.cameraAt(std::nan("")).eye, path.keyframes.front().eye);
    expectVecEq(path.cameraAtFrame(100000).eye, path.keyframes.back().eye);
}

TEST(CameraPath, RespectsNonUniformKeyframeTimes) {
    // Equally spaced collinear points: centripetal Catmull-Rom is then the straight line, traversed linearly
    // in time within each segment, whatever the segments' durations.
    const CameraPath path = parseCameraPath(R"({"version": 1, "keyframes": [
        {"t": 0, "eye": [0, 0, 0], "target": [0, 0, -1]},
        {"t": 1, "eye": [1, 0, 0], "target": [1, 0, -1]},
        {"t": 10, "eye": [2, 0, 0], "target": [2, 0, -1]}]})",
                                            "line");
    EXPECT_NEAR(path.cameraAt(0.5).eye.x, 0.5f, 1e-6f);
    EXPECT_NEAR(path.cameraAt(0.25).eye.x, 0.25f, 1e-6f);
    EXPECT_NEAR(path.cameraAt(5.5).eye.x, 1.5f, 1e-6f);
    EXPECT_NEAR(path.cameraAt(3.25).eye.x, 1.25f, 1e-6f);
    EXPECT_NEAR(path.cameraAt(5.5).eye.y, 0.0f, 1e-6f);
}

TEST(CameraPath, ResolvesCurvedSegmentsWithCentripetalSpline) {
    // A corner with uneven sides; one interior point checked against the Barry-Goldman pyramid by hand.
    // Segment 0: p1 = (0,0), p2 = (4,0), p3 = (4,1), reflected p0 = (-4,0); knots 0, 2, 4, 5 (square roots of
    // the distances); t = 1 is s = 1/2 of [0, 2] -> k = 3.
    const CameraPath path = parseCameraPath(R"({"version": 1, "keyframes": [
        {"t": 0, "eye": [0, 0, 0], "target": [0, 0, -1]},
        {"t": 2, "eye": [4, 0, 0], "target": [0, 0, -1]},
        {"t": 3, "eye": [4, 1, 0], "target": [0, 0, -1]}]})",
                                            "corner");
    // A1 = p0 + 3/2 (p1-p0) = (2,0); A2 = p1 + 1/2 (p2-p1) = (2,0); A3 = p2 + (3-4)/1 (p3-p2) = (4,-1);
    // B1 = A1 + 3/4 (A2-A1) = (2,0); B2 = A2 + 1/3 (A3-A2) = (8/3,-1/3); C = B1 + 1/2 (B2-B1) = (7/3,-1/6).
    const glm::vec3 eye = path.cameraAt(1.0).eye;
    EXPECT_NEAR(eye.x, 7.0f / 3.0f, 1e-5f);
    EXPECT_NEAR(eye.y, -1.0f / 6.0f, 1e-5f);
    EXPECT_EQ(eye.z, 0.0f);
    // The target is the same at all keyframes: it stays exactly still.
    expectVecEq(path.cameraAt(1.0).target, {0, 0, -1});
}

TEST(CameraPath, FrameCountIsRobustToDecimalTimes) {
    const CameraPath path = parseCameraPath(R"({"version": 1, "fps": 10, "keyframes": [
        {"t": 0.1, "eye": [0, 0, 1], "target": [0, 0, 0]},
        {"t": 0.4, "eye": [1, 0, 1], "target": [0, 0, 0]}]})",
                                            "p");
    EXPECT_EQ(path.frameCount(), 4); // frames at 0.1, 0.2, 0.3, 0.4
    EXPECT_NEAR(path.cameraAtFrame(3).eye.x, 1.0f, 1e-6f);
    EXPECT_NEAR(path.cameraAtFrame(1).eye.x, 1.0f / 3.0f, 1e-6f);
}

TEST(CameraPath, JsonRoundTrip) {
    const CameraPath path = parseCameraPath(kValidPath, "walk");
    const std::string json = cameraPathToJson(path);
    const CameraPath again = parseCameraPath(json, "walk");
    EXPECT_EQ(cameraPathToJson(again), json);
    EXPECT_EQ(again.fps, path.fps);
    EXPECT_EQ(again.fovYDegrees, path.fovYDegrees);
    ASSERT_EQ(again.keyframes.size(), path.keyframes.size());
    for (size_t i = 0; i < path.keyframes.size(); ++i) {
        EXPECT_EQ(again.keyframes[i].t, path.keyframes[i].t);
        expectVecEq(again.keyframes[i].eye, path.keyframes[i].eye);
        expectVecEq(again.keyframes[i].target, path.keyframes[i].target);
        expectVecEq(again.keyframes[i].up, path.keyframes[i].up);
    }
    // Floats are written in their shortest form, not as the double they widen to.
    EXPECT_NE(json.find("0.1,"), std::string::npos) << json;
    EXPECT_EQ(json.find("0.10000000149"), std::string::npos) << json;
}

TEST(CameraPath, SaveAndLoad) {
    const fs::path dir = fs::temp_directory_path() / ("chcrt_camera_path_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const CameraPath path = parseCameraPath(kValidPath, "walk");
    saveCameraPath(path, dir / "tour.json");
    const CameraPath loaded = loadCameraPath(dir / "tour.json");
    EXPECT_EQ(loaded.name, "tour");
    EXPECT_EQ(cameraPathToJson(loaded), cameraPathToJson(path));
    EXPECT_THROW(saveCameraPath(path, dir / "missing" / "tour.json"), InputError);
    EXPECT_THROW(loadCameraPath(dir / "missing.json"), InputError);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
    fs::remove_all(dir);
}

TEST(CameraPath, SingleCamera) {
    Camera camera;
    camera.eye = {1, 2, 3};
    camera.fovYDegrees = 35.0f;
    const CameraPath path = singleCameraPath(camera, "cam");
    EXPECT_EQ(path.frameCount(), 1);
    EXPECT_EQ(path.cameraAtFrame(0).fovYDegrees, 35.0f);
    expectVecEq(path.cameraAt(12.0).eye, camera.eye);
    EXPECT_NO_THROW(parseCameraPath(cameraPathToJson(path), "cam"));
}

} // namespace
} // namespace chcrt
