#pragma once
// The out-of-core views of the working set, coloured on the CPU over the shaded frame (pure logic, unit-tested). The
// viewer passes the per-pixel subtrees of the out-of-core primary resolve (outofcore::PrimaryResolve::
// lastPixelSubtrees) and what it knows per subtree. Each subtree gets its own shade of its class's tint and its
// boundaries are drawn dark, so the working set's blocks are visible; the shaded frame's brightness keeps the scene
// readable, and pixels without a hit keep a dimmed grey of it.
//  - `residency` (CHC+RT §5.4, docs/outofcore.md): whether each pixel's primary hit lies in a termination subtree that
//    was already in the GPU subtree cache when the frame started (green) or in one the frame had to upload (orange);
//  - `lod` (chcrt-lod, issue #19): the level of detail its subtree was traced at — the subtree itself (level 0,
//    grey-blue) or one of its proxies (levels 1-4, green to red as they coarsen).
#include <array>
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
// A size mismatch leaves `rgb` untouched and counts nothing.
ResidencyCounts colourResidency(const std::vector<uint32_t>& pixelSubtrees, const std::vector<uint8_t>& residentBefore,
                                int width, int height, std::vector<float>& rgb);

// Levels the lod view tells apart: 0 (the subtree) and the proxy levels a file may hold (kMaxLodLevels).
inline constexpr int kLodViewLevels = 5;
inline constexpr float kLodTints[kLodViewLevels][3] = {
    {0.55f, 0.62f, 0.80f}, {0.20f, 0.85f, 0.30f}, {0.90f, 0.85f, 0.15f}, {1.0f, 0.50f, 0.05f}, {0.95f, 0.15f, 0.10f}};

struct LodCounts {
    uint64_t hitPixels = 0;
    std::array<uint64_t, kLodViewLevels> pixelsPerLevel{}; // hit pixels whose subtree was traced at each level
    uint32_t visibleSubtrees = 0;
};

// `levels[s]`: the level subtree s was traced at this frame (indices past its end and values past the last level
// count as the last level). Arguments otherwise as colourResidency's.
LodCounts colourLod(const std::vector<uint32_t>& pixelSubtrees, const std::vector<uint8_t>& levels, int width,
                    int height, std::vector<float>& rgb);

} // namespace chcrt::app
