#pragma once
// Progress reporting for long steps (loading, BVH build, multi-pass rendering). Library code reports through
// a Progress reference; app/ decides whether it is drawn as a terminal bar (TTY, not --quiet) or discarded.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace chcrt {

class Progress {
public:
    virtual ~Progress() = default;
    // Starts a step with `total` units of work (0 = unknown). A step shorter than a second draws nothing.
    virtual void begin(const std::string& label, uint64_t total) = 0;
    // Starts a step of `items` items (frames) of `unitsPerItem` units each (shader passes): update() counts units,
    // so that a slow item still moves the bar, but a bar names items ("frame 13/300"), what the user asked for.
    virtual void beginItems(const std::string& label, uint64_t items, uint64_t unitsPerItem, const std::string& itemName) {
        (void)itemName;
        begin(label, items * unitsPerItem);
    }
    // Sets the number of completed units. Thread-safe; cheap enough to call per work item.
    virtual void update(uint64_t done) = 0;
    virtual void end() = 0;
};

// A Progress that draws nothing; the default for library callers that do not care.
Progress& nullProgress();

// Terminal progress bar on stderr; draws only when stderr is a TTY and `enabled` is true, and only for steps
// that last longer than a second. Shows percent, elapsed time and an ETA (unknown total: a spinner and the
// count). Redraws at most ~10 times a second from a helper thread that lives from begin() to end(), so
// update() is a single atomic operation. Steps do not nest: begin() during a step ends that step first.
std::unique_ptr<Progress> makeTerminalProgress(bool enabled);

// The same bar with its output and timing made explicit, so tests can observe it without a terminal.
struct TerminalProgressOptions {
    int fd = 2;                // file descriptor the bar is written to
    bool requireTty = true;    // draw only when isatty(fd)
    double delaySeconds = 1.0; // a step draws nothing until it has lasted this long
    double redrawSeconds = 0.1; // how often the helper thread looks at the clock and redraws
    // The clock that times a step (the delay, elapsed time, ETA); empty = std::chrono::steady_clock::now. Tests
    // inject a fixed one, so that what is drawn does not depend on how fast the machine is.
    std::function<std::chrono::steady_clock::time_point()> now;
};
std::unique_ptr<Progress> makeTerminalProgress(bool enabled, const TerminalProgressOptions& options);

} // namespace chcrt
