#version 450 core
// Pure BVH tracing (the baseline every method is compared with), fragment stage: one full-screen pass traces the
// ray of each pixel from the ray textures through the whole BVH (render/trace_ray.glsl) into the hit and cost
// targets. The compute stage (render/trace_bvh.comp.glsl) runs the same code. Host defines: TRACE_ANY_HIT (0 | 1),
// CHCRT_BVH_TRAVERSAL (the file that defines traverseBvh; the Line Space tracer names its own).
#include "render/trace_ray.glsl"

layout(location = CHCRT_TRACE_OUT_HIT) out uvec4 outHit;
layout(location = CHCRT_TRACE_OUT_COST) out uvec4 outCost;

// Early depth test against the active-ray mask (renderer/render/trace_pass.h); also keeps the test early although
// the shader has a side effect (the capped-ray counter).
layout(early_fragment_tests) in;

void main() {
    traceRay(ivec2(gl_FragCoord.xy), outHit, outCost);
}
