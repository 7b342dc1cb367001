// The camera-path JSON reader, then what a render does with a path: its frame count and a camera per frame.
#include "renderer/scene/camera_path.h"
#include "tests/fuzz/fuzz_input.h"

#include <algorithm>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    const std::string text(reinterpret_cast<const char*>(data), size);
    chcrt::fuzz::expectOnlyInputErrors([&] {
        const chcrt::CameraPath path = chcrt::parseCameraPath(text, "fuzz.json");
        const int frames = path.frameCount();
        for (int frame : {0, frames / 2, frames - 1}) (void)path.cameraAtFrame(std::max(frame, 0));
        (void)chcrt::parseCameraPath(chcrt::cameraPathToJson(path), "round trip");
    });
    return 0;
}
