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
                                           bool sceneInCore, const std::optional<ResidencyCounts>& residency,
                                           const std::optional<LodCounts>& lod);

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
    std::optional<LodCounts> lod;
    const ShaftPick* shafts = nullptr; // the shafts view's node
    int width = 0, height = 0, accumulatedFrames = 0;
    double frameMs = 0; // render + visualisation (loop_ms, set afterwards, adds panel and swap)
};

// What the session keeps of its frames. Every frame's JSON (and each loading sample) only for --stats-json, whose
// file lists them all: it grows with the session (a few kB a frame). Otherwise only counters, the graph's last
// kFrameHistory times and, in scripted sessions, two times a frame for the medians of the summary line (room for
// the script's frames allocated at its start), so that a session of any length keeps its memory flat
// (docs/robustness.md, "Long runs").
class ViewerLog {
public:
    static constexpr size_t kFrameHistory = 120;

    ViewerLog(bool keepJson, bool keepTimes) : keepJson_(keepJson), keepTimes_(keepTimes) {}
    void addFrame(const FrameRecord& frame); // numbered in order
    void setLoopMs(double ms);                // of the last frame added: the whole loop iteration
    void addToHistory(float ms);              // the panel's frame-time graph
    // Room for the times of this many frames (keepTimes), allocated once: a scripted session knows its length, and
    // times kept in a vector that doubled as it went freed its old blocks between long-lived ones, a few hundred kB
    // of glibc's heap pinned by each doubling (docs/robustness.md, "Long runs").
    void reserveTimes(size_t frames);
    // A frame that failed (its error); failed frames are not numbered among the rendered ones.
    void addFailure(const std::string& error);
    // A sample of the loading worker's progress; one per change.
    void sampleLoad(const LoadProgressSnapshot& progress, const std::string& scene, double seconds);
    void write(const std::string& file) const; // needs keepJson

    int renderedFrames() const { return renderedFrames_; }
    int failedFrames() const { return failedFrames_; }
    // Medians over the frames (keepTimes): whole loop iterations (frame_ms where a loop time is missing) and the
    // renderer's time; 0 without frames.
    double medianLoopMs() const;
    double medianRendererMs() const;
    const std::deque<float>& history() const { return history_; }

private:
    bool keepJson_, keepTimes_;
    int renderedFrames_ = 0, failedFrames_ = 0;
    nlohmann::json frames_ = nlohmann::json::array();
    nlohmann::json failures_ = nlohmann::json::array();
    nlohmann::json loads_ = nlohmann::json::array();
    std::vector<double> loopMs_, rendererMs_;
    std::deque<float> history_;
};

} // namespace chcrt::app
