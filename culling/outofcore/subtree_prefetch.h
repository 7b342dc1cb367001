#pragma once
// Which termination subtrees to read ahead into the host store while a frame renders (out of core, CHC+RT §5.4):
//  (a) the invisible front next to the visible pairs (ChcrtTracer::collectInvisibleFrontNextToVisible): the
//      termination subtrees that are invisible now but sit beside visible pairs, which a small move of the camera
//      or of the rays turns visible first (upper nodes of that front are left out: choosePrefetchSubtrees says why);
//  (b) the subtrees whose boxes meet the view frustums of the next frames' cameras, when the caller knows them
//      (render and bench walk a camera path; --prefetch-frames K of them), but of those in the current frustum only
//      the ones the current frame asked for: one it did not is hidden, and (a) covers what turns visible (140M city,
//      near path: the next frustums' hidden subtrees were ~20 reads of ~3 MB per frame in frames 1-3, none used,
//      on the CPU the frames needed; a cache smaller than the frame's working set still gets the evicted ones back).
// Each candidate is ranked by its box's distance to the eye that predicts it (the current eye for the front, the
// future eye for a frustum), and the lists are merged nearest first: near subtrees are the likeliest to be hit and
// their misses the likeliest to stall a frame. This file only chooses; SubtreeStore::prefetch reads, bounded by
// the bytes per frame and by the store's budget, and never evicts what the frames use for it.
#include "culling/culling_hierarchy.h"
#include "renderer/render/camera_math.h"

#include <functional>
#include <span>
#include <vector>

namespace chcrt::outofcore {

// True when the box meets the camera's view frustum (side planes and the plane through the eye; the projection
// is infinite, so there is no far plane). Conservative: a box near a frustum's edge may be reported inside.
bool boxMeetsFrustum(const CameraFrame& frame, const glm::vec3& boxMin, const glm::vec3& boxMax);

struct PrefetchRequest {
    std::span<const uint32_t> frontNodes; // nodes of the hierarchy, repeats allowed; termination roots count (a)
    Camera current;                       // the frame just rendered: ranks the front
    std::span<const Camera> next;         // the next frames' cameras, nearest in time first (b)
    int width = 1, height = 1;            // the frames' size (the frustums' aspect)
    // Subtrees the current frame asked for (in the current frustum only these are proposed by (b)); none if empty.
    std::function<bool(uint32_t subtree)> usedNow;
};

// Subtrees (indices into hierarchy.subtrees) in the order to prefetch, each once; `needsNoRead` leaves out those
// that need no read (resident in the GPU cache).
std::vector<uint32_t> choosePrefetchSubtrees(const CullingHierarchy& hierarchy, const PrefetchRequest& request,
                                             const std::function<bool(uint32_t subtree)>& needsNoRead);

} // namespace chcrt::outofcore
