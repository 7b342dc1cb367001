#include "linespace/linespace_image_error.h"

#include "renderer/core/image_io.h"

#include <cmath>
#include <limits>

namespace chcrt::ls {
namespace {

// compareImages reports PSNR with peak 1; back to MSE so frames can be averaged before taking the log.
double mseFromPsnr(double psnrDb) { return std::isinf(psnrDb) ? 0.0 : std::pow(10.0, -psnrDb / 10.0); }
double psnrFromMse(double mse) {
    return mse > 0.0 ? -10.0 * std::log10(mse) : std::numeric_limits<double>::infinity();
}

} // namespace

ImageError measureImageError(Renderer& renderer, Tracer& method, const CameraPath& path, const std::vector<int>& frames,
                             int referenceSupersample) {
    return measureImageError(renderer, method, nullptr, [&renderer](Tracer* t) { renderer.useTracer(t); }, path, frames,
                             referenceSupersample);
}

namespace {

// The reference's frame at `factor`² the pixels, box-filtered to the renderer's size; the renderer's settings are
// restored (also when rendering throws: the benchmark goes on at its own size).
ImageRgba32f renderSupersampled(Renderer& renderer, const Camera& camera, int factor) {
    const RenderSettings settings = renderer.settings();
    RenderSettings large = settings;
    large.width *= factor;
    large.height *= factor;
    ImageRgba32f image;
    try {
        renderer.setSettings(large);
        renderer.renderFrame(camera);
        image = renderer.readDisplayImage();
    } catch (...) {
        renderer.setSettings(settings);
        throw;
    }
    renderer.setSettings(settings);
    return boxFilterDown(image, factor);
}

} // namespace

ImageError measureImageError(Renderer& renderer, Tracer& method, Tracer* reference, const UseTracer& use,
                             const CameraPath& path, const std::vector<int>& frames, int referenceSupersample) {
    ImageError e;
    e.referenceSupersample = referenceSupersample;
    double finalMse = 0.0, indirectMse = 0.0, filteredMse = 0.0, floorMse = 0.0;
    uint64_t over = 0;
    for (int frame : frames) {
        const Camera camera = path.cameraAtFrame(frame);
        use(reference);
        ImageRgba32f filtered;
        if (referenceSupersample > 1) filtered = renderSupersampled(renderer, camera, referenceSupersample);
        renderer.renderFrame(camera);
        const ImageRgba32f exactFinal = renderer.readDisplayImage();
        const ImageRgba32f exactIndirect = renderer.readIndirectImage();
        use(&method);
        renderer.renderFrame(camera);
        const ImageRgba32f approxFinal = renderer.readDisplayImage();
        const ImageRgba32f approxIndirect = renderer.readIndirectImage();
        use(nullptr);
        if (referenceSupersample > 1) {
            filteredMse += mseFromPsnr(compareImages(filtered, approxFinal).psnrDb);
            floorMse += mseFromPsnr(compareImages(filtered, exactFinal).psnrDb);
        }
        const ImageDifference f = compareImages(exactFinal, approxFinal, 2.0f / 255.0f);
        const ImageDifference i = compareImages(exactIndirect, approxIndirect);
        e.finalMae += f.meanAbsoluteError;
        finalMse += mseFromPsnr(f.psnrDb);
        over += f.differingPixels;
        e.indirectMae += i.meanAbsoluteError;
        indirectMse += mseFromPsnr(i.psnrDb);
        e.pixels += uint64_t(exactFinal.width) * uint64_t(exactFinal.height);
        ++e.frames;
    }
    if (e.frames > 0) {
        e.finalMae /= e.frames;
        e.indirectMae /= e.frames;
        e.finalPsnrDb = psnrFromMse(finalMse / e.frames);
        e.indirectPsnrDb = psnrFromMse(indirectMse / e.frames);
        e.finalOver2Of255 = e.pixels > 0 ? double(over) / double(e.pixels) : 0.0;
        if (referenceSupersample > 1) {
            e.filteredPsnrDb = psnrFromMse(filteredMse / e.frames);
            e.samplingFloorPsnrDb = psnrFromMse(floorMse / e.frames);
        }
    }
    return e;
}

} // namespace chcrt::ls
