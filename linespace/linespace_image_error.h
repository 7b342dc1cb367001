#pragma once
// Image error of an approximate tracing method against exact (pure BVH) tracing, as the Line Space issue asks:
// mean absolute error and PSNR of the final shaded image and of the indirect-only image, and the fraction of
// pixels whose final value differs by more than 2/255. Frames are rendered whole with Renderer::renderFrame
// (G-buffer, every effect of the renderer's settings, composition) once per tracer and compared.
#include "renderer/render/renderer.h"
#include "renderer/scene/camera_path.h"

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace chcrt::ls {

struct ImageError {
    int frames = 0;
    uint64_t pixels = 0;
    double finalMae = 0.0;          // display image (tone-mapped, linear [0, 1]), RGB, mean over frames
    double finalPsnrDb = 0.0;       // from the mean MSE over frames; +inf when identical
    double finalOver2Of255 = 0.0;   // fraction of pixels with a channel differing by > 2/255
    double indirectMae = 0.0;       // indirect-only image (linear HDR, clamped to [0, 1]); 0 without diffuse
    double indirectPsnrDb = 0.0;
    // With a supersampled reference (referenceSupersample K > 1): the exact reference rendered at K×K the resolution
    // and box-filtered down (display values averaged) — what the pixel shows with the detail integrated instead of
    // point-sampled. filteredPsnrDb: the method's frame against it; samplingFloorPsnrDb: the exact 1-sample frame's
    // own error against it. An approximation that removes sub-pixel detail (LOD proxies) cannot be closer to a
    // 1-sample exact frame than that frame's sampling error lets it; against the filtered frame the two are
    // compared on the same footing. NaN when not measured.
    int referenceSupersample = 1;
    double filteredPsnrDb = std::numeric_limits<double>::quiet_NaN();
    double samplingFloorPsnrDb = std::numeric_limits<double>::quiet_NaN();
};

// Renders each frame with pure BVH tracing and with `method` and compares. Leaves pure BVH tracing active.
ImageError measureImageError(Renderer& renderer, Tracer& method, const CameraPath& path, const std::vector<int>& frames,
                             int referenceSupersample = 1);

// The same with `reference` as the exact tracer (nullptr: pure BVH), and `use(tracer)` called instead of
// renderer.useTracer before each frame (a tracer may bring its own G-buffer resolve: chcrt-lod, out of core).
// `referenceSupersample` K > 1 also renders each frame with the reference at K×K the resolution (the renderer's
// size is restored after) for filteredPsnrDb and samplingFloorPsnrDb.
using UseTracer = std::function<void(Tracer*)>;
ImageError measureImageError(Renderer& renderer, Tracer& method, Tracer* reference, const UseTracer& use,
                             const CameraPath& path, const std::vector<int>& frames, int referenceSupersample = 1);

} // namespace chcrt::ls
