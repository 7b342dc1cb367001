#pragma once
// The `residency` view of an out-of-core scene (CHC+RT §5.4, docs/outofcore.md): which pixels' primary hits lie
// in a termination subtree that was already in the GPU subtree cache when the frame started (green), and which
// in one the frame had to upload (orange). Each subtree gets its own shade of the tint and its boundaries are
// drawn dark, so the working set's blocks are visible; the shaded frame's brightness keeps the scene readable.
// Pure CPU logic (unit-tested): the viewer passes the per-pixel subtrees of the out-of-core primary resolve
// (outofcore::PrimaryResolve::lastPixelSubtrees) and the cache's residency before the frame.
#include <cstdint>
#include <vector>

namespace chcrt::app {

struct ResidencyCounts {
    uint64_t hitPixels = 0;      // pixels with a primary hit
    uint64_t residentPixels = 0; // ... in a subtree resident before the frame (green)
    uint64_t uploadedPixels = 0; // ... in a subtree uploaded during the frame (orange)
    uint32_t visibleSubtrees = 0; // distinct subtrees of the primary hits
};

// Tints of the two classes (linear display values), exposed for tests.
inline constexpr float kResidentTint[3] = {0.15f, 0.85f, 0.25f};
inline constexpr float kUploadedTint[3] = {1.0f, 0.45f, 0.05f};

// `pixelSubtrees`: width × height values, GL row order (bottom row first), 1 + subtree index, 0 = no hit.
// `residentBefore[s]`: subtree s was resident in the GPU cache when the frame started (indices past its end
// count as not resident). `rgb`: in: the shaded frame (RGB in [0, 1], rows top to bottom); out: the view.
// Pixels without a hit keep a dimmed grey of the shaded frame.
ResidencyCounts colourResidency(const std::vector<uint32_t>& pixelSubtrees, const std::vector<uint8_t>& residentBefore,
                                int width, int height, std::vector<float>& rgb);

} // namespace chcrt::app
