#pragma once
// The viewer's statistics: one frame's counters (CHC+RT's and out of core's as differences of the tracers' running
// totals around the frame), the JSON of each rendered frame and of the loading worker's progress (--stats-json:
// {"frames": [...], "loading": [...]}), and the panel's frame-time graph.
#include "app/viewer/background_job.h"
#include "app/viewer/residency_view.h"
#include "app/viewer/shaft_view.h"
#include "app/viewer/viewer_ui.h"
#include "culling/chcrt_tracer.h"
#include "culling/outofcore/out_of_core_tracer.h"

#include <nlohmann/json.hpp>

#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace chcrt::app {

// One frame's CHC+RT counters: the difference of the tracer's running totals around the frame.
ViewerChcrtStats chcrtFrameStats(const ChcrtStats& before, const ChcrtStats& after);
// Out of core (CHC+RT Table 3) for the frame since `before`, with the budgets and the residency view's counts.
ViewerOutOfCoreStatus outOfCoreFrameStatus(const outofcore::OutOfCoreTracer& tracer, const outofcore::OutOfCoreStats& before,
                                           bool sceneInCore, const std::optional<ResidencyCounts>& residency);

// What a rendered frame's JSON entry holds.
struct FrameRecord {
    const FrameStats* stats = nullptr;
    std::string method, viewMode, primary;
    std::optional<ViewerChcrtStats> chcrt;
    bool alwaysCull = false;
    const outofcore::OutOfCoreTracer* outOfCore = nullptr; // with the frame's status in `outOfCoreStatus`
    std::optional<ViewerOutOfCoreStatus> outOfCoreStatus;
    bool sceneInCore = true;
    std::optional<ResidencyCounts> residency;
    const ShaftPick* shafts = nullptr; // the shafts view's node
    int width = 0, height = 0, accumulatedFrames = 0;
    double frameMs = 0; // render + visualisation (loop_ms, set afterwards, adds panel and swap)
};

class ViewerLog {
public:
    static constexpr size_t kFrameHistory = 120;

    void addFrame(const FrameRecord& frame); // numbered in order
    void setLoopMs(double ms);                // of the last frame added: the whole loop iteration
    void addToHistory(float ms);              // the panel's frame-time graph
    // A sample of the loading worker's progress; one per change.
    void sampleLoad(const LoadProgressSnapshot& progress, const std::string& scene, double seconds);
    void write(const std::string& file) const;

    int renderedFrames() const { return int(frames_.size()); }
    const nlohmann::json& frames() const { return frames_; }
    const std::deque<float>& history() const { return history_; }

private:
    nlohmann::json frames_ = nlohmann::json::array();
    nlohmann::json loads_ = nlohmann::json::array();
    std::deque<float> history_;
};

} // namespace chcrt::app
