#include "renderer/core/frame_range.h"

#include "renderer/core/error.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <utility>

namespace chcrt {

namespace {

// The frames of the longest walkthrough (kMaxCameraPathFrames): stops "0-2000000000" from allocating gigabytes
// before anything renders, and bounds every frame number.
constexpr size_t kMaxFrames = 10'000'000;

std::string_view trim(std::string_view text) {
    const size_t first = text.find_first_not_of(" \t");
    if (first == std::string_view::npos) {
        return {};
    }
    const size_t last = text.find_last_not_of(" \t");
    return text.substr(first, last - first + 1);
}

class FrameRangeParser {
public:
    explicit FrameRangeParser(const std::string& text) : text_(text) {}

    [[noreturn]] void fail(const std::string& why) const {
        throw InputError("frame range \"" + text_ + "\": " + why +
                         " (expected e.g. \"7\", \"1-100\", \"1-100:10\" or \"3,5-9\")");
    }

    // A non-negative decimal integer, nothing else ("-1", "+1", "1.5", "" all fail).
    int parseNumber(std::string_view token, std::string_view item, const char* what) const {
        token = trim(token);
        int value = 0;
        const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
        if (token.empty() || token.front() == '-' || error != std::errc() || end != token.data() + token.size()) {
            std::string shown = "nothing";
            if (!token.empty()) {
                shown.assign(1, '"').append(token).append(1, '"');
            }
            fail("item \"" + std::string(item) + "\" has " + shown + " as its " + what +
                 ", which is not a non-negative integer");
        }
        return value;
    }

    // One item: a frame, or a range first-last with an optional step.
    struct Range {
        int first = 0;
        int last = 0;
        int step = 1;
        size_t count() const { return size_t(last - first) / size_t(step) + 1; }
    };

    // A frame number: at most kMaxFrames - 1, the last frame the longest walkthrough has.
    int parseFrame(std::string_view token, std::string_view item, const char* what) const {
        const int frame = parseNumber(token, item, what);
        if (size_t(frame) >= kMaxFrames) {
            fail("item \"" + std::string(item) + "\" has " + std::to_string(frame) + " as its " + what +
                 ", past the last frame a walkthrough may have (" + std::to_string(kMaxFrames - 1) + ")");
        }
        return frame;
    }

    Range parseItem(std::string_view item) const {
        if (item.empty()) {
            fail("empty item (two commas in a row, or a leading or trailing comma?)");
        }
        Range range;
        const size_t dash = item.find('-', 1); // a leading '-' is a negative number, reported as such
        if (dash == std::string_view::npos) {
            if (item.find(':') != std::string_view::npos) {
                fail("item \"" + std::string(item) + "\" has a step but no range");
            }
            range.first = range.last = parseFrame(item, item, "frame");
            return range;
        }
        range.first = parseFrame(item.substr(0, dash), item, "first frame");
        std::string_view rest = item.substr(dash + 1);
        const size_t colon = rest.find(':');
        if (colon != std::string_view::npos) {
            range.step = parseNumber(rest.substr(colon + 1), item, "step");
            rest = rest.substr(0, colon);
        }
        range.last = parseFrame(rest, item, "last frame");
        if (range.last < range.first) {
            fail("item \"" + std::string(item) + "\" is a reversed range");
        }
        if (range.step == 0) {
            fail("item \"" + std::string(item) + "\" has a zero step");
        }
        return range;
    }

    std::vector<int> parse() const {
        const std::string_view all = text_;
        if (trim(all).empty()) {
            fail("no frames given");
        }
        // Every item is parsed and the frames counted (repeats too) before any is expanded, so a selection too
        // large fails at once and the list is sized once.
        std::vector<Range> ranges;
        size_t count = 0;
        size_t start = 0;
        while (true) {
            const size_t comma = all.find(',', start);
            const std::string_view item = all.substr(start, comma == std::string_view::npos ? all.npos : comma - start);
            ranges.push_back(parseItem(trim(item)));
            count += ranges.back().count();
            if (count > kMaxFrames) {
                fail("selects more than " + std::to_string(kMaxFrames) + " frames");
            }
            if (comma == std::string_view::npos) {
                break;
            }
            start = comma + 1;
        }
        return expand(ranges, count);
    }

    // The frames of `ranges` in order, each once (the first occurrence keeps its place). Repeats are dropped as
    // they are written, with a bitmap over the frames' span (all frames are below kMaxFrames: 1.25 MB at most);
    // a few frames spread wide (fewer than the bitmap's words) are written whole and sorted with their positions
    // instead. A hash set of ints took seconds and half a gigabyte at 10^7 frames; the loops are branch-free
    // plain stores, as 10^7 push_backs and compares cost most of a second in the sanitizer build (tests/fuzz/).
    static std::vector<int> expand(const std::vector<Range>& ranges, size_t count) {
        std::vector<int> frames(count);
        int* out = frames.data();
        int lowest = ranges.front().first, highest = ranges.front().last;
        for (const Range& r : ranges) {
            lowest = std::min(lowest, r.first);
            highest = std::max(highest, r.last);
        }
        const size_t low = size_t(lowest), words = (size_t(highest) - low) / 64 + 1;
        if (ranges.size() > 1 && words <= count) {
            std::vector<uint64_t> seen(words, 0);
            uint64_t* bits = seen.data();
            for (const Range& r : ranges) {
                for (int64_t frame = r.first; frame <= r.last; frame += r.step) {
                    const size_t bit = size_t(frame) - low;
                    const uint64_t word = bits[bit / 64];
                    bits[bit / 64] = word | uint64_t(1) << (bit % 64);
                    *out = int(frame);
                    out += 1 - ((word >> (bit % 64)) & 1); // kept unless already seen
                }
            }
            frames.resize(size_t(out - frames.data()));
            return frames;
        }
        for (const Range& r : ranges) {
            for (int64_t frame = r.first; frame <= r.last; frame += r.step) *out++ = int(frame);
        }
        if (ranges.size() > 1) removeLaterDuplicatesBySorting(frames); // one range never repeats a frame
        return frames;
    }

    static void removeLaterDuplicatesBySorting(std::vector<int>& frames) {
        std::vector<std::pair<int, size_t>> order(frames.size());
        for (size_t i = 0; i < frames.size(); ++i) order[i] = {frames[i], i};
        std::sort(order.begin(), order.end());
        std::vector<char> keep(frames.size(), 0);
        for (size_t i = 0; i < order.size(); ++i) keep[order[i].second] = i == 0 || order[i].first != order[i - 1].first;
        size_t kept = 0;
        for (size_t i = 0; i < frames.size(); ++i) {
            if (keep[i]) frames[kept++] = frames[i];
        }
        frames.resize(kept);
    }

private:
    const std::string& text_;
};

std::string zeroPadded(int value, size_t width) {
    std::string digits = std::to_string(value);
    if (digits.size() < width) {
        digits.insert(0, width - digits.size(), '0');
    }
    return digits;
}

} // namespace

std::vector<int> parseFrameRange(const std::string& text) {
    return FrameRangeParser(text).parse();
}

std::string formatFramePath(const std::string& pattern, int frame, int frameCount) {
    const size_t runEnd = pattern.find_last_of('#');
    if (runEnd != std::string::npos) {
        const size_t before = pattern.find_last_not_of('#', runEnd);
        const size_t runStart = before == std::string::npos ? 0 : before + 1;
        const size_t width = runEnd - runStart + 1;
        return pattern.substr(0, runStart) + zeroPadded(frame, width) + pattern.substr(runEnd + 1);
    }
    if (frameCount == 1) {
        return pattern;
    }
    // At least 4 digits, more when the last frame needs them, so that names sort in frame order.
    const size_t width = std::max<size_t>(4, std::to_string(std::max(0, frameCount - 1)).size());
    std::filesystem::path path(pattern);
    const std::string name = path.stem().string() + "_" + zeroPadded(frame, width) + path.extension().string();
    return path.replace_filename(name).string();
}

} // namespace chcrt
