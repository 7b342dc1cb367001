// The cost debug image of CHC+RT's subtree passes (CHCRT_CULLING_DEBUG_COST; layout in shared/render_layout.h):
// needs `debugImage` and TraceCost (render/bvh_nodes.glsl). Empty without the define.
#ifdef CHCRT_CULLING_DEBUG_COST
// Adds this pass's traversal steps (the pure tracer's cost target counts the same: inner nodes + leaves +
// triangles) to the pixel's count, saturating below the capped bit so that a huge sum never reads as capped.
// Passes over the same pixel are ordered by the tracer's image barriers (the hit image relies on the same), so
// the load-then-add cannot race with another pass's add; the atomics keep each update whole.
void addCostSteps(ivec2 pixel, TraceCost cost) {
    uint steps = cost.innerNodes + cost.leaves + cost.triangles;
    uint counted = imageLoad(debugImage, pixel).x & CHCRT_TRACE_STEPS_COUNT;
    if (steps > CHCRT_TRACE_STEPS_COUNT - counted) {
        imageAtomicOr(debugImage, pixel, CHCRT_TRACE_STEPS_COUNT);
    } else if (steps != 0u) {
        imageAtomicAdd(debugImage, pixel, steps);
    }
    if (cost.iterations >= CHCRT_TRACE_ITERATION_CAP) {
        imageAtomicOr(debugImage, pixel, CHCRT_TRACE_STEPS_CAPPED);
    }
}
#endif
