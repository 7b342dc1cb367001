#pragma once
// What a long run holds, sampled as it runs (render and view): resident memory, open files, threads
// (renderer/core/process_resources.h) and live GL objects (renderer/gl/gl_object_count.h).
//   - resourcesJson(): the `resources` object of every --stats-json frame;
//   - ResourceLog: --resource-log FILE writes one JSON line every --resource-every frames, flushed as it goes, and
//     keeps nothing in memory, so that a run of any length can be sampled (--stats-json keeps every frame's JSON in
//     memory until the end). Each sample first hands the allocator's free pages back (releaseFreedMemory), so that
//     it measures what the process holds. scripts/soak.sh reads it; docs/robustness.md ("Long runs").
#include "renderer/core/process_resources.h"
#include "renderer/gl/gl_object_count.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <string>

namespace chcrt::app {

// {"rss_mb", "open_files", "threads", "gl_objects": {"buffers", ..., "total"}}
nlohmann::json resourcesJson(const ProcessResources& process, const GlObjectCounts& gl);
nlohmann::json sampleResourcesJson(); // of now

class ResourceLog {
public:
    ResourceLog() = default;
    // Creates (truncates) `file`; throws InputError when it cannot. `every` >= 1.
    ResourceLog(const std::string& file, int every);
    ~ResourceLog();
    ResourceLog(const ResourceLog&) = delete;
    ResourceLog& operator=(const ResourceLog&) = delete;
    ResourceLog(ResourceLog&& o) noexcept;
    ResourceLog& operator=(ResourceLog&& o) noexcept;

    bool enabled() const { return out_ != nullptr; }
    // Frame `frame` (0-based, counted by the caller) is done: a line when frame % every == 0 or `last` (once per
    // frame). `extra` fields (the method, the scene) are added to the line. Throws InputError when the write fails.
    void frameDone(uint64_t frame, bool last = false, const nlohmann::json& extra = nlohmann::json::object());

private:
    std::string file_;
    std::FILE* out_ = nullptr;
    int every_ = 100;
    int64_t lastWritten_ = -1;
};

} // namespace chcrt::app
