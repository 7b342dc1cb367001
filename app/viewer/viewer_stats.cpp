#include "app/viewer/viewer_stats.h"

#include "app/outofcore_report.h"
#include "app/report.h"
#include "app/resource_log.h"
#include "renderer/core/statistics.h"

namespace chcrt::app {
namespace {

nlohmann::json statsToJson(const FrameStats& s) {
    nlohmann::json trace = nlohmann::json::object();
    for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
        const TraceStats& t = s.trace[size_t(type)];
        trace[toString(type)] = {{"passes", t.passes}, {"ms", t.milliseconds}};
    }
    return {{"gbuffer_ms", s.gbufferMs}, {"raygen_ms", s.raygenMs}, {"trace_ms", s.traceMs()},
            {"shade_ms", s.shadeMs},     {"renderer_ms", s.totalMs}, {"trace", trace},
            {"rays_generated", s.raysGenerated}, {"capped_rays", s.cappedRays}};
}

nlohmann::json chcrtStatsToJson(const ViewerChcrtStats& c) {
    return {{"traces", c.traces},         {"queries", c.queries},       {"subtrees_scheduled", c.subtreesScheduled},
            {"shader_calls", c.shaderCalls}, {"phase1_ms", c.phase1Ms}, {"phase2_ms", c.phase2Ms},
            {"phase3_ms", c.phase3Ms},     {"fallback_ms", c.fallbackMs}, {"fallback_traces", c.fallbackTraces},
            {"queries_skipped_extent", c.queriesSkippedExtent}, {"culled_traces", c.culledTraces()},
            {"mean_height", c.meanHeight()}};
}

} // namespace

ViewerChcrtStats chcrtFrameStats(const ChcrtStats& before, const ChcrtStats& after) {
    ViewerChcrtStats f;
    f.traces = after.traces - before.traces;
    f.queries = after.queries - before.queries;
    f.queriesSkippedExtent = after.queriesSkippedExtent - before.queriesSkippedExtent;
    f.subtreesScheduled = after.subtreesScheduled - before.subtreesScheduled;
    f.shaderCalls = after.shaderCalls - before.shaderCalls;
    f.phase1Ms = after.phase1Ms - before.phase1Ms;
    f.phase2Ms = after.phase2Ms - before.phase2Ms;
    f.phase3Ms = after.phase3Ms - before.phase3Ms;
    f.fallbackMs = after.fallbackMs - before.fallbackMs;
    f.fallbackTraces = after.fallbackTraces - before.fallbackTraces;
    f.heightSum = after.heightSum - before.heightSum;
    return f;
}

ViewerOutOfCoreStatus outOfCoreFrameStatus(const outofcore::OutOfCoreTracer& tracer, const outofcore::OutOfCoreStats& before,
                                           bool sceneInCore, const std::optional<ResidencyCounts>& residency,
                                           const std::optional<LodCounts>& lod) {
    ViewerOutOfCoreStatus o;
    o.frame = outofcore::OutOfCoreStats::difference(tracer.snapshot(), before);
    o.gpuCacheMb = double(tracer.options().gpuCacheBytes) / double(1u << 20);
    o.hostCacheMb = double(tracer.options().hostCacheBytes) / double(1u << 20);
    o.fileSubtrees = tracer.file().subtrees().size();
    o.sceneInCore = sceneInCore;
    o.residency = residency;
    o.lod = lod;
    return o;
}

void ViewerLog::addFrame(const FrameRecord& f) {
    ++renderedFrames_;
    if (keepTimes_) {
        loopMs_.push_back(f.frameMs); // until setLoopMs
        rendererMs_.push_back(f.stats->totalMs);
    }
    if (!keepJson_) return;
    nlohmann::json entry = statsToJson(*f.stats);
    entry["frame"] = frames_.size();
    entry["method"] = f.method;
    entry["view_mode"] = f.viewMode;
    entry["primary"] = f.primary;
    if (f.chcrt) {
        entry["chcrt"] = chcrtStatsToJson(*f.chcrt);
        entry["chcrt"]["always_cull"] = f.alwaysCull;
    }
    if (f.outOfCore && f.outOfCoreStatus) {
        entry["outofcore"] = outOfCoreStatsJson(f.outOfCoreStatus->frame, 1.0, *f.outOfCore);
        entry["outofcore"]["scene_in_core"] = f.sceneInCore;
    }
    if (f.residency) {
        const ResidencyCounts& c = *f.residency;
        entry["residency"] = {{"hit_pixels", c.hitPixels}, {"resident_pixels", c.residentPixels},
                              {"uploaded_pixels", c.uploadedPixels}, {"visible_subtrees", c.visibleSubtrees}};
    }
    if (f.lod) {
        const LodCounts& c = *f.lod;
        entry["lod"] = {{"hit_pixels", c.hitPixels}, {"pixels_per_level", c.pixelsPerLevel},
                        {"visible_subtrees", c.visibleSubtrees}};
    }
    if (f.shafts) {
        const ShaftPick& p = *f.shafts;
        entry["shafts"] = {{"pixel", {p.pixelX, p.pixelY}}, {"space", p.space},     {"spaces", p.spaceCount},
                           {"bvh_node", p.bvhNode},         {"triangles", p.subtreeTriangles},
                           {"n", p.n}, {"depth", p.depth},  {"t", p.triangleThreshold},
                           {"shafts", p.shafts},            {"filled", p.filled}, {"fill_rate", p.fillRate()},
                           {"build_ms", p.buildMs}};
    }
    entry["width"] = f.width;
    entry["height"] = f.height;
    entry["accumulated_frames"] = f.accumulatedFrames;
    entry["frame_ms"] = f.frameMs;
    entry["resources"] = sampleResourcesJson();
    frames_.push_back(std::move(entry));
}

void ViewerLog::reserveTimes(size_t frames) {
    if (!keepTimes_) return;
    loopMs_.reserve(frames);
    rendererMs_.reserve(frames);
}

void ViewerLog::setLoopMs(double ms) {
    if (keepTimes_ && !loopMs_.empty()) loopMs_.back() = ms;
    if (!frames_.empty()) frames_.back()["loop_ms"] = ms;
}

void ViewerLog::addFailure(const std::string& error) {
    ++failedFrames_;
    if (keepJson_) failures_.push_back({{"after_frame", renderedFrames_}, {"error", error}});
}

double ViewerLog::medianLoopMs() const { return loopMs_.empty() ? 0.0 : median(loopMs_); }
double ViewerLog::medianRendererMs() const { return rendererMs_.empty() ? 0.0 : median(rendererMs_); }

void ViewerLog::addToHistory(float ms) {
    history_.push_back(ms);
    if (history_.size() > kFrameHistory) history_.pop_front();
}

void ViewerLog::sampleLoad(const LoadProgressSnapshot& p, const std::string& scene, double seconds) {
    if (!keepJson_) return;
    nlohmann::json sample = {{"scene", scene},   {"step", p.step},   {"label", p.label},
                             {"done", p.done},   {"total", p.total}, {"fraction", p.fraction()},
                             {"complete", p.complete}};
    if (!loads_.empty()) { // one sample per change
        nlohmann::json last = loads_.back();
        last.erase("seconds");
        if (last == sample) return;
    }
    sample["seconds"] = seconds;
    loads_.push_back(std::move(sample));
}

void ViewerLog::write(const std::string& file) const {
    writeJsonFile(file, nlohmann::json{{"frames", frames_}, {"failed_frames", failures_}, {"loading", loads_}});
}

} // namespace chcrt::app
