#include "app/viewer/viewer_method.h"

#include "app/methods.h"
#include "app/outofcore_report.h"
#include "renderer/core/error.h"

#include <unistd.h>

namespace chcrt::app {

PrivateCacheDirectory::~PrivateCacheDirectory() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
}

void PrivateCacheDirectory::create() {
    const std::filesystem::path base = std::filesystem::temp_directory_path();
    for (int attempt = 0; path_.empty(); ++attempt) {
        const std::filesystem::path candidate =
            base / ("chcrt-view-" + std::to_string(::getpid()) + "-" + std::to_string(attempt));
        if (std::filesystem::create_directory(candidate)) path_ = candidate; // false: it exists, try the next
    }
}

std::string MethodSwitcher::tracerKey(const ViewerSettings& s) {
    return s.method + (s.chcrtAlwaysCull ? " always-cull " : " ") + methodParameters(s.common);
}

bool MethodSwitcher::changed(const ViewerSettings& s) const {
    return activeMethod_.empty() || s.method != activeMethod_ || s.chcrtAlwaysCull != activeAlwaysCull_ ||
           methodParameters(s.common) != activeParameters_;
}

ChcrtTracer* MethodSwitcher::chcrt() const {
    return outOfCore_ ? &outOfCore_->chcrt() : dynamic_cast<ChcrtTracer*>(tracer_.get());
}

const std::filesystem::path& MethodSwitcher::usePrivateCache() {
    if (privateCache_.path().empty()) privateCache_.create();
    return privateCache_.path();
}

void MethodSwitcher::sceneChanged() {
    discardJob(cacheJob_); // it reads the previous scene's BVH (its result stays in the disk cache)
    cacheWarmKey_.clear();
    releaseTracer();
    activeMethod_.clear();
}

void MethodSwitcher::offerPremade(std::unique_ptr<Tracer> tracer, std::string key) {
    premade_ = std::move(tracer);
    premadeKey_ = std::move(key);
}

void MethodSwitcher::releaseTracer() {
    outOfCore_ = nullptr;
    tracer_.reset();
}

void MethodSwitcher::apply(ViewerSettings& settings, SceneSession& scene, Renderer& renderer) {
    if (!changed(settings)) return;
    const std::string previous = activeMethod_;
    const std::string& m = settings.method;
    const bool tracesOutOfCore = m == kRasterOnlyMethod ? scene.sceneInCore : findGpuMethod(m).outOfCoreForm;
    if (scene.options.outOfCoreScene.enabled && !tracesOutOfCore && !previous.empty()) {
        // Refused before the current tracer is destroyed: its GPU cache (and CHC+RT fronts) stay as they are.
        notice_("method " + m + " has no out-of-core form (pure BVH and Line Space tracing need the whole scene on "
                "the GPU); keeping " + previous);
        settings.method = previous;
        if (!changed(settings)) return;
    }
    // Methods read their parameters from the session's options (app/methods.cpp).
    copyMethodParameters(settings.common, scene.options);
    if (!prepareCache(settings, scene)) return; // building on the worker: the current tracer keeps rendering meanwhile
    activeParameters_ = methodParameters(settings.common);
    renderer.useTracer(nullptr);
    renderer.setOutOfCorePrimary({}); // it points into the out-of-core tracer destroyed next
    releaseTracer(); // first: an out-of-core tracer's GPU cache is freed before the next one is allocated
    createWithFallback(settings, scene, previous);
    outOfCore_ = dynamic_cast<outofcore::OutOfCoreTracer*>(tracer_.get());
    // Not in core: the G-buffer is resolved through this tracer's recorded primary subtrees (as chcrt render).
    if (outOfCore_ && needsOutOfCorePrimary(*outOfCore_, scene.sceneInCore)) installOutOfCorePrimary(renderer, *outOfCore_);
    renderer.useTracer(tracer_.get());
    activeMethod_ = settings.method;
    activeAlwaysCull_ = settings.chcrtAlwaysCull;
}

std::unique_ptr<Tracer> MethodSwitcher::create(const std::string& method, const ViewerSettings& settings,
                                               const SceneSession& scene) {
    if (method == kRasterOnlyMethod) {
        // Its traced primary rays use the renderer's pure BVH, which holds nothing out of core.
        if (!scene.sceneInCore) throw InputError("method raster needs the scene in core; use chcrt");
        return nullptr;
    }
    if (premade_ && method == settings.method && premadeKey_ == tracerKey(settings)) {
        return std::move(premade_); // made by the loading worker
    }
    return makeTracer(method, scene, settings.chcrtAlwaysCull); // nullptr for "bvh": the renderer's own
}

// Refused methods (no out-of-core form) or parameters (e.g. a visibility threshold for exact CHC+RT): in core back
// to pure BVH; out of core back to the previous method, else chcrt with default parameters.
void MethodSwitcher::createWithFallback(ViewerSettings& settings, SceneSession& scene, const std::string& previous) {
    try {
        tracer_ = create(settings.method, settings, scene);
        return;
    } catch (const InputError& error) {
        const bool outOfCore = scene.options.outOfCoreScene.enabled;
        const std::string fallback = !outOfCore                                          ? kPureBvhMethod
                                     : !previous.empty() && previous != settings.method ? previous
                                                                                        : "chcrt";
        notice_(std::string("method ") + settings.method + ": " + error.what() + "; using " + fallback);
        settings.method = fallback;
        if (!outOfCore) return;
    }
    try {
        tracer_ = create(settings.method, settings, scene);
    } catch (const InputError&) { // the parameters are refused: chcrt with its defaults (budget errors propagate)
        copyMethodParameters(CommonOptions{}, settings.common);
        copyMethodParameters(settings.common, scene.options);
        activeParameters_ = methodParameters(settings.common);
        settings.method = "chcrt";
        tracer_ = create("chcrt", settings, scene);
    }
}

// True when the method's Line Spaces / N-tree are in the disk cache (or it needs none): makeTracer then only loads
// them. Otherwise their build runs on cacheJob_ and this returns false until it has finished (a change of method
// or parameters meanwhile starts the next build once it is done). Scripts wait for the build in place, so that
// their frames and screenshots show the method they switched to.
bool MethodSwitcher::prepareCache(const ViewerSettings& settings, const SceneSession& scene) {
    const std::string key = settings.method + " " + methodParameters(settings.common);
    if (key == cacheWarmKey_) return true;
    if (cacheJob_.busy()) {
        if (!cacheJob_.finished() && !scripted_) return false;
        const std::string built = cacheJob_.name();
        try {
            cacheJob_.take();
        } catch (const InputError& error) { // e.g. an unwritable --ls-cache: makeTracer reports it again
            notice_(std::string("building for ") + built + ": " + error.what());
        }
        if (built == key) {
            cacheWarmKey_ = key;
            return true;
        }
    }
    std::function<void(Progress&)> job =
        settings.method == kRasterOnlyMethod ? nullptr : methodCacheBuild(settings.method, scene);
    if (!job) {
        cacheWarmKey_ = key;
        return true;
    }
    cacheJob_.start(key, std::move(job));
    notice_("building the Line Spaces of " + settings.method + " on a worker thread into " +
            scene.options.lineSpaceTracing.cacheDirectory +
            (privateCache_.path().empty() ? "" : " (private to this session: --ls-cache \"\")"));
    if (!scripted_) return false;
    return prepareCache(settings, scene); // waits for it
}

} // namespace chcrt::app
