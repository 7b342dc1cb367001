#include "app/viewer/viewer_ui.h"

#include "app/parameters.h"

#include "renderer/core/error.h"

#include <imgui.h>

#include <cstdio>
#include <imgui_stdlib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cfloat>
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
    // The panel stays inside the window: its height follows its content up to the window's bottom edge (below that
    // it scrolls), its width is the user's (kPanelWidth at first; the resize grip changes it). Long text wraps.
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const float maxWidth = std::max(kMinPanelWidth, display.x - 2 * kPanelMargin);
    const float maxHeight = std::max(kMinPanelHeight, display.y - top_ - kPanelMargin);
    ImGui::SetNextWindowPos(ImVec2(kPanelMargin, kPanelMargin), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(std::min(width_, maxWidth), 0.0f), ImGuiCond_Always); // 0: fit the content
    ImGui::SetNextWindowSizeConstraints(ImVec2(kMinPanelWidth, kMinPanelHeight), ImVec2(maxWidth, maxHeight));
    ImGui::Begin("chcrt view");
    width_ = ImGui::GetWindowWidth();
    top_ = std::max(0.0f, ImGui::GetWindowPos().y);
    // Sliders and inputs leave room for their labels on the right.
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 9.0f);
    ImGui::PushTextWrapPos(0.0f); // text wraps at the panel's right edge
    if (!status.frameError.empty()) {
        ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "frame not rendered: %s", status.frameError.c_str());
    }
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
    if (ImGui::CollapsingHeader("Rendering", ImGuiTreeNodeFlags_DefaultOpen)) drawSettings(settings, status, actions);
    if (ImGui::CollapsingHeader("Camera and paths", ImGuiTreeNodeFlags_DefaultOpen)) drawCamera(status, actions);
    if (ImGui::CollapsingHeader("Scene")) {
        ImGui::Text("%s: %llu triangles", status.sceneName.c_str(), static_cast<unsigned long long>(status.triangles));
        ImGui::SetNextItemWidth(-ImGui::CalcTextSize("Load").x - 3 * ImGui::GetStyle().ItemSpacing.x);
        ImGui::InputText("##scene", &sceneField_);
        ImGui::SameLine();
        ImGui::BeginDisabled(status.loading);
        if (ImGui::Button("Load")) actions.loadScene = sceneField_;
        ImGui::EndDisabled();
    }
    if (!status.message.empty()) ImGui::TextWrapped("%s", status.message.c_str());
    ImGui::PopTextWrapPos();
    ImGui::PopItemWidth();
    ImGui::End();
    return actions;
}

void ViewerPanel::drawStatistics(const ViewerStatus& status) {
    const FrameStats& s = status.stats;
    graphSize_ = {0.0f, 0.0f};
    if (!status.frameRendered) { // loading the first scene: no frame, so no frame time, size or split to show
        ImGui::TextUnformatted("no frame rendered yet");
        return;
    }
    // Of the last rendered frame: frames that the loop does not render (a complete view) do not count.
    ImGui::Text("%.1f fps, frame %.2f ms", status.frameMs > 0 ? 1000.0 / status.frameMs : 0.0, status.frameMs);
    ImGui::SameLine();
    ImGui::Text(" internal %d x %d", status.internalWidth, status.internalHeight);
    if (!status.frameHistoryMs.empty()) {
        const float top = *std::max_element(status.frameHistoryMs.begin(), status.frameHistoryMs.end());
        // An explicit width: this ImGui's PlotLines takes a negative width as it is (a graph -1 px wide, drawn as a
        // one-pixel line) instead of "up to the right edge".
        const float width = std::max(ImGui::GetContentRegionAvail().x, 1.0f);
        ImGui::PlotLines("##frames", status.frameHistoryMs.data(), int(status.frameHistoryMs.size()), 0,
                         "frame time (ms)", 0.0f, std::max(top * 1.1f, 1.0f), ImVec2(width, kGraphHeight));
        graphSize_ = {ImGui::GetItemRectSize().x, ImGui::GetItemRectSize().y};
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
        // What the adaptive choice ran (culling/adaptive_choice.h): culling at which height, or pure passes.
        if (c.culledTraces() > 0) {
            ImGui::Text("  %llu of %llu traces culled, mean termination height %.1f",
                        static_cast<unsigned long long>(c.culledTraces()), static_cast<unsigned long long>(c.traces),
                        c.meanHeight());
        } else if (c.traces > 0) {
            ImGui::Text("  all %llu traces as pure passes (adaptive fallback)", static_cast<unsigned long long>(c.traces));
        }
        ImGui::Text("  %llu queries (%llu skipped: out of the rays' reach)", static_cast<unsigned long long>(c.queries),
                    static_cast<unsigned long long>(c.queriesSkippedExtent));
        ImGui::Text("  %llu subtrees scheduled, %llu shader calls", static_cast<unsigned long long>(c.subtreesScheduled),
                    static_cast<unsigned long long>(c.shaderCalls));
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
    ImGui::Text("  peak %.1f MB; GPU peak %.1f MB", double(f.hostPeakResidentBytes) * mb, double(f.peakResidentBytes) * mb);
    ImGui::Text("prefetch: %llu reads, %llu hits, %.2f MB wasted", count(f.prefetchReads), count(f.prefetchHits),
                double(f.prefetchWastedBytes) * mb);
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
    if (o.lod) {
        const LodCounts& l = *o.lod;
        const double hits = double(std::max<uint64_t>(l.hitPixels, 1));
        ImGui::Text("levels of %llu hit pixels (%u subtrees):", count(l.hitPixels), l.visibleSubtrees);
        for (int level = 0; level < kLodViewLevels; ++level) {
            if (l.pixelsPerLevel[size_t(level)] == 0) continue;
            ImGui::TextColored(ImVec4(kLodTints[level][0], kLodTints[level][1], kLodTints[level][2], 1),
                               level == 0 ? "  %.1f %% the subtrees" : "  %.1f %% proxy level %d",
                               100.0 * double(l.pixelsPerLevel[size_t(level)]) / hits, level);
        }
    }
}

void ViewerPanel::drawSettings(ViewerSettings& settings, const ViewerStatus& status, ViewerActions& actions) {
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
    drawPrimaryVisibility(settings, changes);
    drawMethodParameters(settings, status, changes);
    drawEffects(settings, changes);
    const CommonOptions shown = shownParameters(settings, status.triangles);
    for (const Parameter& p : parameterTable()) {
        if (p.area == ParameterArea::Render) drawParameter(p, shown, changes);
    }
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

// Primary visibility: rasterised G-buffer, or primary rays traced with the method's tracer (CHC+RT §5 "Prim").
// The raster-only method traces its primary rays (when chosen) with pure BVH and no secondary rays.
void ViewerPanel::drawPrimaryVisibility(const ViewerSettings& settings, nlohmann::json& changes) {
    bool traced = settings.common.render.primaryVisibility == PrimaryVisibility::Traced || settings.sceneNotInCore;
    ImGui::BeginDisabled(settings.sceneNotInCore); // out of core: always out-of-core primary rays
    if (ImGui::Checkbox("trace primary rays", &traced)) changes["primary"] = traced ? "traced" : "raster";
    ImGui::EndDisabled();
    if (settings.sceneNotInCore && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
        ImGui::SetTooltip("the scene is not in core: primary visibility comes from out-of-core primary rays");
    }
}

// The sections of the method's parameter areas (app/methods.h MethodInfo::areas), each parameter's widget from
// the table. Each change recreates the tracer (CHC+RT's visibility fronts start again; Line Spaces and N-trees
// are rebuilt or loaded from the cache on a worker).
void ViewerPanel::drawMethodParameters(ViewerSettings& settings, const ViewerStatus& status, nlohmann::json& changes) {
    const MethodInfo* method = viewerMethod(settings);
    const CommonOptions shown = shownParameters(settings, status.triangles);
    const auto section = [&](ParameterArea area) {
        for (const Parameter& p : parameterTable()) {
            if (p.area == area) drawParameter(p, shown, changes);
        }
    };
    if (method && method->reads(ParameterArea::Chcrt) && ImGui::TreeNode("CHC+RT parameters")) {
        bool alwaysCull = settings.chcrtAlwaysCull;
        if (ImGui::Checkbox("always cull (no adaptive fallback)", &alwaysCull)) changes["chcrtAlwaysCull"] = alwaysCull;
        section(ParameterArea::Chcrt);
        if (method->reads(ParameterArea::ChcrtVisibility)) section(ParameterArea::ChcrtVisibility);
        ImGui::TreePop();
    }
    const bool lineSpaces = method && method->reads(ParameterArea::LineSpace);
    if ((lineSpaces || settings.viewMode == ViewMode::Shafts) && ImGui::TreeNode("Line Space parameters")) {
        section(ParameterArea::LineSpace); // N/D/T also drive the shafts view
        ImGui::TreePop();
    }
    if (method && method->reads(ParameterArea::NTree) && ImGui::TreeNode("N-tree parameters")) {
        section(ParameterArea::NTree); // the soft-shadow paper's N-tree: each change rebuilds it
        ImGui::TreePop();
    }
}

void ViewerPanel::drawEffects(const ViewerSettings& settings, nlohmann::json& changes) {
    EffectSet effects = settings.common.render.effects;
    bool effectsChanged = ImGui::Checkbox("shadows", &effects.shadows);
    ImGui::SameLine();
    effectsChanged |= ImGui::Checkbox("AO", &effects.ao);
    ImGui::SameLine();
    ImGui::BeginDisabled(settings.sceneNotInCore); // bounce hits are shaded by id over the whole scene
    effectsChanged |= ImGui::Checkbox("diffuse", &effects.diffuse);
    ImGui::EndDisabled();
    if (effectsChanged) changes["effects"] = toString(effects);
}

// One parameter's widget (ParameterWidget), showing its value in `shown`; a change goes to `changes` under its key.
void ViewerPanel::drawParameter(const Parameter& p, const CommonOptions& shown, nlohmann::json& changes) {
    const ParameterWidget& w = p.widget;
    using Kind = ParameterWidget::Kind;
    if (w.kind == Kind::None || w.kind == Kind::Custom || p.key.empty()) return;
    if (w.sameLine) ImGui::SameLine();
    const nlohmann::json value = p.json(shown);
    switch (w.kind) {
    case Kind::Slider:
    case Kind::LogSlider:
        if (value.is_number_integer()) {
            int v = value.get<int>();
            if (ImGui::SliderInt(w.label, &v, int(w.min), int(w.max))) changes[p.key] = v;
        } else {
            float v = value.get<float>();
            const ImGuiSliderFlags flags = w.kind == Kind::LogSlider ? ImGuiSliderFlags_Logarithmic : 0;
            if (ImGui::SliderFloat(w.label, &v, w.min, w.max, w.format ? w.format : "%.3f", flags)) changes[p.key] = v;
        }
        break;
    case Kind::InputInt: {
        int v = value.get<int>();
        if (ImGui::InputInt(w.label, &v) && v >= 0) changes[p.key] = v;
        break;
    }
    case Kind::Checkbox: {
        bool v = value.get<bool>();
        if (ImGui::Checkbox(w.label, &v)) changes[p.key] = v;
        break;
    }
    case Kind::Combo: {
        const std::string current = value.get<std::string>();
        if (ImGui::BeginCombo(w.label, current.c_str())) {
            for (const std::string& choice : p.choices) {
                if (ImGui::Selectable(choice.c_str(), choice == current)) changes[p.key] = choice;
            }
            ImGui::EndCombo();
        }
        break;
    }
    case Kind::PairSliders: { // "A:B"
        int a = 0, b = 0;
        std::sscanf(value.get<std::string>().c_str(), "%d:%d", &a, &b);
        bool changed = ImGui::SliderInt(w.label, &a, int(w.min), int(w.max));
        changed |= ImGui::SliderInt(w.secondLabel, &b, int(w.secondMin), int(w.secondMax));
        if (changed) changes[p.key] = std::to_string(a) + ":" + std::to_string(b);
        break;
    }
    case Kind::None:
    case Kind::Custom: break;
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
    ImGui::SetNextItemWidth(-FLT_MIN); // up to the right edge (it has no label)
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
