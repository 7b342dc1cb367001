#include "renderer/core/frame_range.h"

#include "renderer/core/error.h"

#include <charconv>
#include <filesystem>
#include <string_view>
#include <unordered_set>

namespace chcrt {

namespace {

// Enough for any walkthrough; stops "0-2000000000" from allocating gigabytes before anything renders.
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

    void parseItem(std::string_view item, std::vector<int>& frames, std::unordered_set<int>& seen) const {
        if (item.empty()) {
            fail("empty item (two commas in a row, or a leading or trailing comma?)");
        }
        int first = 0;
        int last = 0;
        int step = 1;
        const size_t dash = item.find('-', 1); // a leading '-' is a negative number, reported as such
        if (dash == std::string_view::npos) {
            if (item.find(':') != std::string_view::npos) {
                fail("item \"" + std::string(item) + "\" has a step but no range");
            }
            first = last = parseNumber(item, item, "frame");
        } else {
            first = parseNumber(item.substr(0, dash), item, "first frame");
            std::string_view rest = item.substr(dash + 1);
            const size_t colon = rest.find(':');
            if (colon != std::string_view::npos) {
                step = parseNumber(rest.substr(colon + 1), item, "step");
                rest = rest.substr(0, colon);
            }
            last = parseNumber(rest, item, "last frame");
            if (last < first) {
                fail("item \"" + std::string(item) + "\" is a reversed range");
            }
            if (step == 0) {
                fail("item \"" + std::string(item) + "\" has a zero step");
            }
        }
        // Checked before expanding, counting duplicates, so a huge range fails at once.
        const size_t count = size_t(last - first) / size_t(step) + 1;
        if (frames.size() + count > kMaxFrames) {
            fail("selects more than " + std::to_string(kMaxFrames) + " frames");
        }
        for (long long frame = first; frame <= last; frame += step) {
            if (seen.insert(int(frame)).second) {
                frames.push_back(int(frame));
            }
        }
    }

    std::vector<int> parse() const {
        std::vector<int> frames;
        std::unordered_set<int> seen;
        const std::string_view all = text_;
        if (trim(all).empty()) {
            fail("no frames given");
        }
        size_t start = 0;
        while (true) {
            const size_t comma = all.find(',', start);
            const std::string_view item = all.substr(start, comma == std::string_view::npos ? all.npos : comma - start);
            parseItem(trim(item), frames, seen);
            if (comma == std::string_view::npos) {
                break;
            }
            start = comma + 1;
        }
        return frames;
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
