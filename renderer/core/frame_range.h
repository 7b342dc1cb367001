#pragma once
// Frame selections as the CLI's --frames takes them: "1-100", "1-100:10" (every 10th), "3,5-9", "7".
// Frames are 0-based indices into a camera path (frame k is at time k / fps).
#include <string>
#include <vector>

namespace chcrt {

// Throws InputError for malformed text, negative numbers, reversed ranges or a zero step. Duplicates are
// kept in order of appearance removed (first occurrence wins); the result is never empty.
std::vector<int> parseFrameRange(const std::string& text);

// Replaces the last run of '#' in `pattern` with the zero-padded frame number ("out_####.png" + 7 ->
// "out_0007.png"); a pattern without '#' is returned unchanged when `frameCount` == 1, otherwise the number
// is inserted before the extension ("out.png" -> "out_0007.png").
std::string formatFramePath(const std::string& pattern, int frame, int frameCount);

} // namespace chcrt
