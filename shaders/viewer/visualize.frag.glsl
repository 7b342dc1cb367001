#version 450 core
// The viewer's display image at the internal resolution, in linear display values [0, 1] (the window blit and
// PNG writing apply the sRGB transfer function). One mode per view mode of app/viewer/view_modes.h.
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/viewer_layout.h"
#include "shared/culling_layout.h"

layout(binding = CHCRT_VIEWER_UNIT_DISPLAY) uniform sampler2D renderedDisplay;
layout(binding = CHCRT_VIEWER_UNIT_ACCUM) uniform sampler2D accumulatedHdr;
layout(binding = CHCRT_VIEWER_UNIT_COST) uniform usampler2D traversalCost;
layout(binding = CHCRT_VIEWER_UNIT_CULLING_COST) uniform usampler2D cullingCost;
layout(binding = CHCRT_UNIT_GBUFFER_POSITION) uniform sampler2D gbufferPosition;
layout(binding = CHCRT_UNIT_GBUFFER_NORMAL) uniform sampler2D gbufferNormal;
layout(binding = CHCRT_UNIT_GBUFFER_ALBEDO) uniform sampler2D gbufferAlbedo;
layout(binding = CHCRT_UNIT_GBUFFER_TRIANGLE) uniform usampler2D gbufferTriangle;

uniform int viewMode;
uniform int accumulatedFrames; // frames summed in accumulatedHdr; <= 1 shows the renderer's own frame
uniform float exposure;
uniform vec3 sceneLower;
uniform vec3 sceneExtent;
uniform float sceneDiagonal;
uniform float costScale; // traversal steps at the top of the heat map (log scale: costs span orders of magnitude)
// Cost view of CHC+RT methods: the steps come from CHC+RT's cost debug image (steps summed over its subtree passes,
// bit 31 = capped; culling/culling_layout.h) instead of the tracer's cost target, on the same heat map and scale.
uniform bool useCullingCost;

layout(location = 0) out vec4 outDisplay;

// The renderer's tone curve (shading/compose.frag.glsl), applied to the mean of the accumulated frames.
vec3 toneMapAces(vec3 x) {
    return clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

// PCG-style integer hash: distinct colours for neighbouring triangle ids.
vec3 hashColour(uint id) {
    uint h = id * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    h = (h >> 22u) ^ h;
    return vec3(float(h & 255u), float((h >> 8u) & 255u), float((h >> 16u) & 255u)) / 255.0f * 0.85f + 0.15f;
}

// Black → blue → cyan → green → yellow → red → white over [0, 1].
vec3 heat(float x) {
    const vec3 stops[7] = vec3[7](vec3(0.0f), vec3(0.0f, 0.0f, 1.0f), vec3(0.0f, 1.0f, 1.0f), vec3(0.0f, 1.0f, 0.0f),
                                  vec3(1.0f, 1.0f, 0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(1.0f));
    float s = clamp(x, 0.0f, 1.0f) * 6.0f;
    int i = min(int(s), 5);
    return mix(stops[i], stops[i + 1], s - float(i));
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    bool covered = texelFetch(gbufferTriangle, pixel, 0).x != CHCRT_NO_HIT_ID;
    vec3 colour = vec3(0.0f);
    if (viewMode == CHCRT_VIEW_SHADED) {
        if (accumulatedFrames <= 1) {
            colour = texelFetch(renderedDisplay, pixel, 0).rgb;
        } else {
            vec4 sum = texelFetch(accumulatedHdr, pixel, 0);
            colour = toneMapAces(sum.rgb / max(sum.a, 1.0f) * exposure);
        }
    } else if (viewMode == CHCRT_VIEW_COST) {
        uint steps = 0u;
        bool capped = false;
        if (useCullingCost) {
            uint value = texelFetch(cullingCost, pixel, 0).x;
            steps = value & CHCRT_TRACE_STEPS_COUNT;
            capped = (value & CHCRT_TRACE_STEPS_CAPPED) != 0u;
        } else {
            uvec4 cost = texelFetch(traversalCost, pixel, 0);
            steps = cost.x + cost.y + cost.z;
            capped = cost.w != 0u;
        }
        // Magenta: the ray reached the loop cap (its cost is cut short).
        colour = capped ? vec3(1.0f, 0.0f, 1.0f) : heat(log2(1.0f + float(steps)) / log2(1.0f + costScale));
    } else if (covered) {
        if (viewMode == CHCRT_VIEW_POSITION) {
            colour = (texelFetch(gbufferPosition, pixel, 0).xyz - sceneLower) / max(sceneExtent, vec3(1e-6f));
        } else if (viewMode == CHCRT_VIEW_NORMAL) {
            colour = 0.5f + 0.5f * texelFetch(gbufferNormal, pixel, 0).xyz;
        } else if (viewMode == CHCRT_VIEW_ALBEDO) {
            colour = texelFetch(gbufferAlbedo, pixel, 0).rgb;
        } else if (viewMode == CHCRT_VIEW_TRIANGLE) {
            colour = hashColour(texelFetch(gbufferTriangle, pixel, 0).x);
        } else if (viewMode == CHCRT_VIEW_DEPTH) {
            float depth = texelFetch(gbufferNormal, pixel, 0).w;
            colour = vec3(1.0f - log(1.0f + depth) / log(1.0f + max(sceneDiagonal, 1e-3f)));
        }
    }
    outDisplay = vec4(clamp(colour, 0.0f, 1.0f), 1.0f);
}
