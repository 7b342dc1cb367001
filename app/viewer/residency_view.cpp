#include "app/viewer/residency_view.h"

#include <algorithm>
#include <functional>
#include <unordered_set>

namespace chcrt::app {
namespace {

// A brightness in [0.55, 1] per subtree, so that neighbouring subtrees of the same class are told apart.
float subtreeShade(uint32_t subtree) {
    uint32_t h = subtree * 0x9E3779B1u;
    h ^= h >> 15;
    h *= 0x85EBCA77u;
    h ^= h >> 13;
    return 0.55f + 0.45f * float(h & 255u) / 255.0f;
}

// Colours every hit pixel with the tint `tintOf(subtree)` chooses (shaded, per-subtree shade, dark boundaries), the
// others a dimmed grey. Returns the distinct subtrees hit, or -1 (nothing done) when the sizes do not match.
int64_t colourBySubtree(const std::vector<uint32_t>& pixelSubtrees, int width, int height, std::vector<float>& rgb,
                        const std::function<const float*(uint32_t subtree)>& tintOf) {
    const size_t n = size_t(width) * size_t(height);
    if (pixelSubtrees.size() != n || rgb.size() != n * 3) return -1;
    std::unordered_set<uint32_t> visible;
    // Value of the pixel at (x, y) with y counted from the top (rgb's order); pixelSubtrees has GL order.
    const auto at = [&](int x, int y) { return pixelSubtrees[size_t(height - 1 - y) * width + x]; };
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            float* out = &rgb[(size_t(y) * width + x) * 3];
            const float luminance = std::clamp(0.2126f * out[0] + 0.7152f * out[1] + 0.0722f * out[2], 0.0f, 1.0f);
            const uint32_t v = at(x, y);
            if (v == 0) {
                for (int c = 0; c < 3; ++c) out[c] = 0.35f * luminance;
                continue;
            }
            const uint32_t subtree = v - 1;
            visible.insert(subtree);
            const float* tint = tintOf(subtree);
            // A pixel whose right or lower neighbour belongs to another subtree (or none) lies on a boundary.
            const bool boundary = (x + 1 < width && at(x + 1, y) != v) || (y + 1 < height && at(x, y + 1) != v);
            const float scale = subtreeShade(subtree) * (0.45f + 0.55f * luminance) * (boundary ? 0.3f : 1.0f);
            for (int c = 0; c < 3; ++c) out[c] = std::clamp(tint[c] * scale, 0.0f, 1.0f);
        }
    }
    return int64_t(visible.size());
}

} // namespace

ResidencyCounts colourResidency(const std::vector<uint32_t>& pixelSubtrees, const std::vector<uint8_t>& residentBefore,
                                int width, int height, std::vector<float>& rgb) {
    ResidencyCounts counts;
    const int64_t visible = colourBySubtree(pixelSubtrees, width, height, rgb, [&](uint32_t subtree) {
        const bool resident = subtree < residentBefore.size() && residentBefore[subtree] != 0;
        ++counts.hitPixels;
        (resident ? counts.residentPixels : counts.uploadedPixels) += 1;
        return resident ? kResidentTint : kUploadedTint;
    });
    counts.visibleSubtrees = uint32_t(std::max<int64_t>(visible, 0));
    return counts;
}

LodCounts colourLod(const std::vector<uint32_t>& pixelSubtrees, const std::vector<uint8_t>& levels, int width,
                    int height, std::vector<float>& rgb) {
    LodCounts counts;
    const int64_t visible = colourBySubtree(pixelSubtrees, width, height, rgb, [&](uint32_t subtree) {
        const int level = std::min(subtree < levels.size() ? int(levels[subtree]) : kLodViewLevels - 1,
                                   kLodViewLevels - 1);
        ++counts.hitPixels;
        ++counts.pixelsPerLevel[size_t(level)];
        return kLodTints[level];
    });
    counts.visibleSubtrees = uint32_t(std::max<int64_t>(visible, 0));
    return counts;
}

} // namespace chcrt::app
