#pragma once
// Progress reporting for long steps (loading, BVH build, multi-pass rendering). Library code reports through
// a Progress reference; app/ decides whether it is drawn as a terminal bar (TTY, not --quiet) or discarded.
#include <cstdint>
#include <memory>
#include <string>

namespace chcrt {

class Progress {
public:
    virtual ~Progress() = default;
    // Starts a step with `total` units of work (0 = unknown). A step shorter than a second draws nothing.
    virtual void begin(const std::string& label, uint64_t total) = 0;
    // Sets the number of completed units. Thread-safe; cheap enough to call per work item.
    virtual void update(uint64_t done) = 0;
    virtual void end() = 0;
};

// A Progress that draws nothing; the default for library callers that do not care.
Progress& nullProgress();

// Terminal progress bar on stderr; draws only when stderr is a TTY and `enabled` is true, and only for steps
// that last longer than a second. Shows percent, elapsed time and an ETA.
std::unique_ptr<Progress> makeTerminalProgress(bool enabled);

} // namespace chcrt
