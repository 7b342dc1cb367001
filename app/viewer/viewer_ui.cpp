#include "app/viewer/viewer_ui.h"

#include "renderer/core/error.h"

#include <imgui.h>

#include <cstdio>
#include <imgui_stdlib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace chcrt::app {
namespace {

void row(const char* label, double milliseconds) {
    ImGui::Text("  %-18s %8.2f ms", label, milliseconds);
}

// Rays per second over tracing time; counts every generated ray (inactive ones included, like FrameStats).
double megaRaysPerSecond(const FrameStats& s) {
    const double ms = s.traceMs();
    return ms > 0 ? double(s.raysGenerated) / (ms * 1e3) : 0.0;
}

} // namespace

ViewerActions ViewerPanel::draw(ViewerSettings& settings, const ViewerStatus& status) {
    ViewerActions actions;
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(360, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("chcrt view");
    if (status.loading) { // first, so that it is visible however small the window
        // Loading and the BVH build run on a worker thread; the elapsed time and a spinner show it is alive.
        const char spinner[] = "|/-\\";
        ImGui::Text("Loading %s %c %.1f s", status.loadingScene.c_str(),
                    spinner[int(status.loadingSeconds * 8) & 3], status.loadingSeconds);
        // The worker's Progress: the step (scene loading/generation, BVH build) and its fraction when known.
        if (!status.loadingStep.empty()) {
            ImGui::Text("step %d: %s", status.loadingStepNumber, status.loadingStep.c_str());
            if (status.loadingFraction >= 0) {
                char text[32];
                std::snprintf(text, sizeof(text), "%.0f %%", 100.0 * status.loadingFraction);
                ImGui::ProgressBar(float(status.loadingFraction), ImVec2(-1, 0), text);
            }
        }
    }
    drawStatistics(status);
    if (settings.viewMode == ViewMode::Shafts && !status.shaftInfo.empty() &&
        ImGui::CollapsingHeader("Line Space shafts", ImGuiTreeNodeFlags_DefaultOpen)) {
        for (const std::string& line : status.shaftInfo) ImGui::TextUnformatted(line.c_str());
    }
    if (ImGui::CollapsingHeader("Rendering", ImGuiTreeNodeFlags_DefaultOpen)) drawSettings(settings, actions);
    if (ImGui::CollapsingHeader("Camera and paths", ImGuiTreeNodeFlags_DefaultOpen)) drawCamera(status, actions);
    if (ImGui::CollapsingHeader("Scene")) {
        ImGui::Text("%s: %llu triangles", status.sceneName.c_str(), static_cast<unsigned long long>(status.triangles));
        ImGui::InputText("##scene", &sceneField_);
        ImGui::SameLine();
        ImGui::BeginDisabled(status.loading);
        if (ImGui::Button("Load")) actions.loadScene = sceneField_;
        ImGui::EndDisabled();
    }
    if (!status.message.empty()) ImGui::TextWrapped("%s", status.message.c_str());
    ImGui::End();
    return actions;
}

void ViewerPanel::drawStatistics(const ViewerStatus& status) {
    const FrameStats& s = status.stats;
    ImGui::Text("%.1f fps  frame %.2f ms  internal %d x %d", status.frameMs > 0 ? 1000.0 / status.frameMs : 0.0,
                status.frameMs, status.internalWidth, status.internalHeight);
    if (!status.frameHistoryMs.empty()) {
        const float top = *std::max_element(status.frameHistoryMs.begin(), status.frameHistoryMs.end());
        ImGui::PlotLines("##frames", status.frameHistoryMs.data(), int(status.frameHistoryMs.size()), 0,
                         "frame time (ms)", 0.0f, std::max(top * 1.1f, 1.0f), ImVec2(-1, 50));
    }
    ImGui::Text("renderer %.2f ms, accumulated frames %d", s.totalMs, status.accumulatedFrames);
    row("G-buffer", s.gbufferMs);
    row("ray generation", s.raygenMs);
    for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
        const TraceStats& t = s.trace[size_t(type)];
        if (t.passes == 0) continue;
        const std::string label = std::string("trace ") + toString(type) + " (" + std::to_string(t.passes) + ")";
        row(label.c_str(), t.milliseconds);
    }
    if (status.chcrt) {
        // CHC+RT Algorithm 1's phases, summed over the frame's traces (they are inside the trace rows above).
        const ViewerChcrtStats& c = *status.chcrt;
        row("  CHC+RT phase 1", c.phase1Ms);
        row("  CHC+RT phase 2", c.phase2Ms);
        row("  CHC+RT phase 3", c.phase3Ms);
        if (c.fallbackTraces > 0) row("  CHC+RT fallback", c.fallbackMs);
        ImGui::Text("  %llu queries (%llu skipped: out of the rays' reach), %llu subtrees scheduled, %llu shader calls",
                    static_cast<unsigned long long>(c.queries), static_cast<unsigned long long>(c.queriesSkippedExtent),
                    static_cast<unsigned long long>(c.subtreesScheduled), static_cast<unsigned long long>(c.shaderCalls));
    }
    row("shading", s.shadeMs);
    ImGui::Text("%.2f Mrays/s (%llu rays)", megaRaysPerSecond(s), static_cast<unsigned long long>(s.raysGenerated));
    if (s.cappedRays > 0) {
        ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "%llu rays reached the loop cap",
                           static_cast<unsigned long long>(s.cappedRays));
    }
    if (status.outOfCore && ImGui::CollapsingHeader("Out of core (Table 3, this frame)", ImGuiTreeNodeFlags_DefaultOpen)) {
        drawOutOfCore(*status.outOfCore);
    }
}

void ViewerPanel::drawOutOfCore(const ViewerOutOfCoreStatus& o) {
    // The columns of CHC+RT Table 3 for the frame's traces (all ray sets): docs/outofcore.md.
    const outofcore::OutOfCoreStats& f = o.frame;
    const double mb = 1.0 / double(1u << 20);
    const auto count = [](uint64_t v) { return static_cast<unsigned long long>(v); };
    ImGui::Text("%.2f Mrays/s, %llu queries", f.traceMs > 0 ? double(f.raysTraced) / (f.traceMs * 1e3) : 0.0,
                count(f.queries));
    ImGui::Text("  over %.1f ms of CHC+RT tracing", f.traceMs);
    ImGui::Text("cache: %llu hits, %llu misses", count(f.cacheHits), count(f.cacheMisses));
    ImGui::Text("  %llu evictions, %llu deferred", count(f.cacheEvictions), count(f.cacheDeferred));
    if (f.cachePostponed > 0) {
        ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "streaming: %llu subtrees postponed (frame incomplete)",
                           count(f.cachePostponed));
    }
    ImGui::Text("uploaded: %.2f MB BVH", double(f.uploadedBvhBytes) * mb);
    ImGui::Text("  + %.2f MB geometry", double(f.uploadedGeometryBytes) * mb);
    ImGui::Text("GPU: %.1f MB resident / %.1f MB", double(f.residentBytes) * mb, double(f.allocatedBytes) * mb);
    ImGui::Text("  (budget %.0f MB), %u of %u slots used", o.gpuCacheMb, f.residentSubtrees, f.slots);
    ImGui::Text("  the file has %zu subtrees", o.fileSubtrees);
    ImGui::Text("host: %llu reads, %.2f MB read", count(f.hostReads), double(f.hostBytesRead) * mb);
    ImGui::Text("  %.1f MB resident (budget %.0f MB)", double(f.hostResidentBytes) * mb, o.hostCacheMb);
    if (o.sceneInCore) ImGui::TextUnformatted("scene also in core (--load-in-core): G-buffer from the in-core data");
    if (o.residency) {
        const ResidencyCounts& r = *o.residency;
        const double hits = double(std::max<uint64_t>(r.hitPixels, 1));
        ImGui::Text("residency of %llu hit pixels (%u subtrees):", count(r.hitPixels), r.visibleSubtrees);
        ImGui::TextColored(ImVec4(kResidentTint[0], kResidentTint[1], kResidentTint[2], 1),
                           "  %.1f %% resident before the frame", 100.0 * double(r.residentPixels) / hits);
        ImGui::TextColored(ImVec4(kUploadedTint[0], kUploadedTint[1], kUploadedTint[2], 1),
                           "  %.1f %% uploaded this frame", 100.0 * double(r.uploadedPixels) / hits);
    }
}

void ViewerPanel::drawSettings(ViewerSettings& settings, ViewerActions& actions) {
    // Edits go through applySettings, the same validation the scripts use; invalid values are refused.
    nlohmann::json changes = nlohmann::json::object();
    const std::vector<std::string> methods = viewerMethods();
    if (ImGui::BeginCombo("method", settings.method.c_str())) {
        for (const std::string& m : methods) {
            if (ImGui::Selectable(m.c_str(), m == settings.method)) changes["method"] = m;
        }
        ImGui::EndCombo();
    }
    if (ImGui::BeginCombo("view", toString(settings.viewMode))) {
        for (ViewMode mode : allViewModes()) {
            if (ImGui::Selectable(toString(mode), mode == settings.viewMode)) changes["viewMode"] = toString(mode);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", describe(mode));
        }
        ImGui::EndCombo();
    }
    // Primary visibility: rasterised G-buffer, or primary rays traced with the method's tracer (CHC+RT §5 "Prim").
    // The raster-only method traces its primary rays (when chosen) with pure BVH and no secondary rays.
    bool traced = settings.common.primary == "traced" || settings.sceneNotInCore;
    ImGui::BeginDisabled(settings.sceneNotInCore); // out of core: always out-of-core primary rays
    if (ImGui::Checkbox("trace primary rays", &traced)) changes["primary"] = traced ? "traced" : "raster";
    ImGui::EndDisabled();
    if (settings.sceneNotInCore && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
        ImGui::SetTooltip("the scene is not in core: primary visibility comes from out-of-core primary rays");
    }
    if (settings.method.rfind("chcrt", 0) == 0 && ImGui::TreeNode("CHC+RT parameters")) {
        // Each change recreates the tracer (its visibility fronts start again); culling/README.md, CHC+RT §5.
        const CommonOptions& c = settings.common;
        bool alwaysCull = settings.chcrtAlwaysCull;
        if (ImGui::Checkbox("always cull (no adaptive fallback)", &alwaysCull)) changes["chcrtAlwaysCull"] = alwaysCull;
        int minTile = c.chcrtMinTile < 0 ? 64 : c.chcrtMinTile;
        if (ImGui::SliderInt("min tile (px)", &minTile, 8, 256)) changes["chcrtMinTile"] = minTile;
        int height = c.chcrtHeight < 0 ? 24 : c.chcrtHeight;
        if (ImGui::SliderInt("subtree height", &height, 2, 32)) changes["chcrtHeight"] = height;
        int multi = c.chcrtMultiQuery < 0 ? 4 : c.chcrtMultiQuery;
        if (ImGui::SliderInt("pairs per multi-query", &multi, 1, 16)) changes["chcrtMultiQuery"] = multi;
        bool tighter = c.chcrtTighterBounds != "off";
        if (ImGui::Checkbox("tighter bounds", &tighter)) changes["chcrtTighterBounds"] = tighter;
        ImGui::SameLine();
        bool leafCache = c.chcrtLeafCache == "on"; // default off (culling/README.md: slower on llvmpipe)
        if (ImGui::Checkbox("leaf cache", &leafCache)) changes["chcrtLeafCache"] = leafCache;
        ImGui::SameLine();
        bool merged = c.chcrtMergedBatch != "off"; // default on (culling/README.md, "Merged batch traversal")
        if (ImGui::Checkbox("merged batches", &merged)) changes["chcrtMergedBatch"] = merged;
        bool rayExtent = c.chcrtRayExtent != "off"; // culling/ray_extent_grid.h
        if (ImGui::Checkbox("ray extent culling", &rayExtent)) changes["chcrtRayExtent"] = rayExtent;
        if (settings.method == "chcrt-aggressive") {
            int threshold = c.chcrtThreshold < 0 ? 20 : c.chcrtThreshold;
            if (ImGui::SliderInt("visible threshold (rays)", &threshold, 0, 200)) changes["chcrtThreshold"] = threshold;
        }
        ImGui::TreePop();
    }
    if ((settings.method.find("+ls") != std::string::npos || settings.viewMode == ViewMode::Shafts) &&
        ImGui::TreeNode("Line Space parameters")) { // N/D/T also drive the shafts view
        // Each change rebuilds (or loads from the cache) the Line Space: the window waits for it.
        const CommonOptions& c = settings.common;
        int n = int(c.lsN), depth = int(c.lsDepth), t = int(c.lsT);
        if (ImGui::SliderInt("N (patches per edge)", &n, 1, 16)) changes["lsN"] = n;
        if (ImGui::SliderInt("depth D", &depth, 1, 16)) changes["lsDepth"] = depth;
        if (ImGui::SliderInt("T", &t, 1, 32)) changes["lsT"] = t;
        float angle = c.lsAngle;
        if (ImGui::SliderFloat("candidate angle", &angle, 0.0f, 90.0f, "%.0f deg")) changes["lsAngle"] = angle;
        if (settings.method == "ntree+ls") {
            // The soft-shadow paper's N-tree (--ls-ntree N:d and its shadow options): each change rebuilds it.
            int treeN = 6, treeD = 3;
            std::sscanf(c.lsNtree.empty() ? "6:3" : c.lsNtree.c_str(), "%d:%d", &treeN, &treeD);
            bool treeChanged = ImGui::SliderInt("N-tree N", &treeN, 2, 16);
            treeChanged |= ImGui::SliderInt("N-tree depth d", &treeD, 1, 8);
            if (treeChanged) changes["lsNtree"] = std::to_string(treeN) + ":" + std::to_string(treeD);
            int level = c.lsNtreeLevel;
            if (ImGui::SliderInt("shadow level (-1 = d-1)", &level, -1, 8)) changes["lsNtreeLevel"] = level;
            bool exactStart = c.lsNtreeStart == "exact";
            if (ImGui::Checkbox("exact start node", &exactStart)) changes["lsNtreeStart"] = exactStart ? "exact" : "skip";
            float nearEdges = c.lsNtreeNear;
            if (ImGui::SliderFloat("near (node edges)", &nearEdges, 0.0f, 8.0f, "%.2f")) changes["lsNtreeNear"] = nearEdges;
        }
        ImGui::TreePop();
    }
    EffectSet effects = parseEffects(settings.common.effects);
    bool effectsChanged = ImGui::Checkbox("shadows", &effects.shadows);
    ImGui::SameLine();
    effectsChanged |= ImGui::Checkbox("AO", &effects.ao);
    ImGui::SameLine();
    ImGui::BeginDisabled(settings.sceneNotInCore); // bounce hits are shaded by id over the whole scene
    effectsChanged |= ImGui::Checkbox("diffuse", &effects.diffuse);
    ImGui::EndDisabled();
    if (effectsChanged) changes["effects"] = toString(effects);
    int spp = settings.common.spp;
    if (ImGui::SliderInt("spp", &spp, 1, 16)) changes["spp"] = spp;
    float rotation = settings.common.rotation;
    if (ImGui::SliderFloat("rotation", &rotation, 0.0f, 360.0f, "%.0f deg")) changes["rotation"] = rotation;
    float aoLength = settings.common.aoLength;
    if (ImGui::SliderFloat("AO length", &aoLength, 0.001f, 0.2f, "%.3f", ImGuiSliderFlags_Logarithmic)) {
        changes["aoLength"] = aoLength;
    }
    float exposure = settings.common.exposure;
    if (ImGui::SliderFloat("exposure", &exposure, 0.05f, 8.0f, "%.2f", ImGuiSliderFlags_Logarithmic)) {
        changes["exposure"] = exposure;
    }
    int seed = int(settings.common.seed);
    if (ImGui::InputInt("seed", &seed) && seed >= 0) changes["seed"] = seed;
    float scale = settings.renderScale;
    if (ImGui::SliderFloat("render scale", &scale, 0.1f, 1.0f, "%.2f")) changes["renderScale"] = scale;
    bool accumulate = settings.accumulate;
    if (ImGui::Checkbox("refine when still", &accumulate)) changes["accumulate"] = accumulate;
    if (settings.viewMode == ViewMode::Cost || isChcrtDebugMode(settings.viewMode)) {
        int type = int(settings.costRayType);
        const char* types[] = {"primary", "shadow", "ao", "diffuse"};
        if (ImGui::Combo("cost rays", &type, types, 4)) changes["costRayType"] = types[type];
        float costScale = settings.costScale;
        if (ImGui::SliderFloat("cost scale", &costScale, 10.0f, 100000.0f, "%.0f steps",
                               ImGuiSliderFlags_Logarithmic)) {
            changes["costScale"] = costScale;
        }
    }
    if (!changes.empty()) {
        try {
            applySettings(settings, changes);
            actions.settingsChanged = true;
        } catch (const InputError&) {
            // Out-of-range slider input: keep the previous settings.
        }
    }
}

void ViewerPanel::drawCamera(const ViewerStatus& status, ViewerActions& actions) {
    const Camera& c = status.camera;
    ImGui::Text("eye    %.2f %.2f %.2f", c.eye.x, c.eye.y, c.eye.z);
    ImGui::Text("target %.2f %.2f %.2f", c.target.x, c.target.y, c.target.z);
    ImGui::Text("speed %.3g units/s (scroll, +/-; shift x5)", status.speed);
    actions.reset = ImGui::Button("Reset (R)");
    ImGui::SameLine();
    actions.frameScene = ImGui::Button("Frame scene (F)");
    actions.togglePlay = ImGui::Button(status.playing ? "Pause path (P)" : "Play path (P)");
    ImGui::SameLine();
    int frame = status.pathFrame;
    if (ImGui::SliderInt("##pathframe", &frame, 0, std::max(status.pathFrames - 1, 0))) actions.pathFrame = frame;
    actions.toggleRecord = ImGui::Button(status.recording ? "Stop recording (F9)" : "Record walkthrough (F9)");
    if (status.recording) {
        ImGui::SameLine();
        ImGui::Text("%zu keyframes", status.recordedKeyframes);
    }
    actions.screenshot = ImGui::Button("Screenshot (F12)");
    ImGui::SameLine();
    actions.copyCommandLine = ImGui::Button("Copy command line (C)");
}

} // namespace chcrt::app
