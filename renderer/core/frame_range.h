#pragma once
// Frame selections as the CLI's --frames takes them: "1-100", "1-100:10" (every 10th), "3,5-9", "7".
// Frames are 0-based indices into a camera path (frame k is at time k / fps).
#include <string>
#include <vector>

namespace chcrt {

// Returns the selected frames in order of appearance with duplicates removed (the first occurrence keeps
// its place: "5,1-6" -> 5,1,2,3,4,6); the result is never empty. Spaces around items are allowed. Throws
// InputError for malformed text, negative numbers, reversed ranges, a zero step, frame numbers of 10^7 or more
// (past the end of the longest walkthrough) or more than 10^7 frames (repeats counted).
std::vector<int> parseFrameRange(const std::string& text);

// Replaces the last run of '#' in `pattern` with the zero-padded frame number ("out_####.png" + 7 ->
// "out_0007.png"; a longer number is not truncated); a pattern without '#' is returned unchanged when
// `frameCount` == 1, otherwise the number (at least 4 digits, more if frameCount - 1 needs them) is inserted
// before the extension of the file name ("out.png" -> "out_0007.png").
std::string formatFramePath(const std::string& pattern, int frame, int frameCount);

} // namespace chcrt
