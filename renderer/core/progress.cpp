#include "renderer/core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>

namespace chcrt {

namespace {

class NullProgress final : public Progress {
public:
    void begin(const std::string&, uint64_t) override {}
    void update(uint64_t) override {}
    void end() override {}
};

using Clock = std::chrono::steady_clock;

// "m:ss" below an hour, "h:mm:ss" above.
std::string formatDuration(double seconds) {
    const auto total = static_cast<long long>(std::max(0.0, seconds));
    char text[32];
    if (total >= 3600) {
        std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", total / 3600, total / 60 % 60, total % 60);
    } else {
        std::snprintf(text, sizeof text, "%lld:%02lld", total / 60, total % 60);
    }
    return text;
}

// Draws from a helper thread so that update() stays one atomic read-modify-write: the hot loops that report
// progress (BVH build, tracing) never touch the clock, a lock or the terminal.
class TerminalProgress final : public Progress {
public:
    explicit TerminalProgress(const TerminalProgressOptions& options) : options_(options) {}
    ~TerminalProgress() override { end(); }

    void begin(const std::string& label, uint64_t total) override { start(label, total, 0, ""); }

    void beginItems(const std::string& label, uint64_t items, uint64_t unitsPerItem, const std::string& itemName) override {
        start(label, items * unitsPerItem, unitsPerItem, itemName);
    }

    void update(uint64_t done) override {
        // Keep the maximum so that workers reporting out of order never move the bar backwards.
        uint64_t current = done_.load(std::memory_order_relaxed);
        while (done > current && !done_.compare_exchange_weak(current, done, std::memory_order_relaxed)) {
        }
    }

    void end() override {
        if (!drawer_.joinable()) {
            return;
        }
        {
            std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_all();
        drawer_.join();
        // Finish the line only if the step was long enough to be drawn at all.
        if (drawn_) {
            draw(true);
        }
    }

private:
    void start(const std::string& label, uint64_t total, uint64_t unitsPerItem, const std::string& itemName) {
        end();
        unitsPerItem_ = unitsPerItem;
        itemName_ = itemName;
        // Long labels would wrap the line and break the '\r' redraw.
        label_ = label.size() > 32 ? label.substr(0, 29) + "..." : label;
        total_ = total;
        done_.store(0, std::memory_order_relaxed);
        start_ = now();
        drawn_ = false;
        lastLength_ = 0;
        frame_ = 0;
        stopping_ = false;
        drawer_ = std::thread([this] { drawLoop(); });
    }

    void drawLoop() {
        const auto period = std::chrono::duration<double>(options_.redrawSeconds);
        std::unique_lock lock(mutex_);
        while (!wake_.wait_for(lock, period, [this] { return stopping_; })) {
            if (elapsedSeconds() >= options_.delaySeconds) {
                draw(false);
                drawn_ = true;
            }
        }
    }

    Clock::time_point now() const { return options_.now ? options_.now() : Clock::now(); }
    double elapsedSeconds() const { return std::chrono::duration<double>(now() - start_).count(); }

    void draw(bool finished) {
        const double elapsed = elapsedSeconds();
        const uint64_t done = done_.load(std::memory_order_relaxed);
        std::string line = "\r" + label_ + " ";
        char text[160];
        if (total_ > 0) {
            const double fraction = std::min(1.0, double(done) / double(total_));
            constexpr int kBarWidth = 24;
            const int filled = static_cast<int>(fraction * kBarWidth);
            line += '[';
            line.append(size_t(filled), '#').append(size_t(kBarWidth - filled), '.');
            line += ']';
            if (unitsPerItem_ > 0) { // the item being worked on, of all items: "frame 13/300"
                const uint64_t items = total_ / unitsPerItem_;
                const uint64_t current = done >= total_ ? items : std::min(items, done / unitsPerItem_ + 1);
                std::snprintf(text, sizeof text, " %3d%% %s %llu/%llu %s", static_cast<int>(fraction * 100.0),
                              itemName_.c_str(), static_cast<unsigned long long>(current),
                              static_cast<unsigned long long>(items), formatDuration(elapsed).c_str());
            } else {
                std::snprintf(text, sizeof text, " %3d%% %llu/%llu %s", static_cast<int>(fraction * 100.0),
                              static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_),
                              formatDuration(elapsed).c_str());
            }
            line += text;
            if (!finished && done > 0 && done < total_) {
                const double eta = elapsed * double(total_ - done) / double(done);
                line += " ETA " + formatDuration(std::ceil(eta)); // "0:00" only when done
            }
        } else {
            static constexpr char kSpinner[] = "|/-\\";
            const char spin = finished ? ' ' : kSpinner[frame_++ % 4];
            std::snprintf(text, sizeof text, "%c %llu %s", spin, static_cast<unsigned long long>(done),
                          formatDuration(elapsed).c_str());
            line += text;
        }
        // Pad with spaces so a shorter line fully overwrites the previous one.
        const size_t length = line.size();
        if (length < lastLength_) {
            line += std::string(lastLength_ - length, ' ');
        }
        lastLength_ = length;
        if (finished) {
            line += "\n";
        }
        writeAll(line);
    }

    void writeAll(const std::string& text) const {
        size_t written = 0;
        while (written < text.size()) {
            const ssize_t n = ::write(options_.fd, text.data() + written, text.size() - written);
            if (n <= 0) {
                return; // a progress bar is never worth failing the run for
            }
            written += size_t(n);
        }
    }

    TerminalProgressOptions options_;
    std::string label_;
    uint64_t total_ = 0;
    uint64_t unitsPerItem_ = 0; // beginItems: units per item (0: the bar counts units)
    std::string itemName_;
    std::atomic<uint64_t> done_{0};
    Clock::time_point start_{};
    bool drawn_ = false;
    size_t lastLength_ = 0;
    unsigned frame_ = 0;

    std::thread drawer_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
};

} // namespace

Progress& nullProgress() {
    static NullProgress progress;
    return progress;
}

std::unique_ptr<Progress> makeTerminalProgress(bool enabled) {
    return makeTerminalProgress(enabled, TerminalProgressOptions{});
}

std::unique_ptr<Progress> makeTerminalProgress(bool enabled, const TerminalProgressOptions& options) {
    if (!enabled || (options.requireTty && !::isatty(options.fd))) {
        return std::make_unique<NullProgress>();
    }
    return std::make_unique<TerminalProgress>(options);
}

} // namespace chcrt
