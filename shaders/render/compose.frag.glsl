#version 450 core
// Deferred shading: combines the G-buffer with the accumulated effects and tone-maps.
//   L = direct (soft-shadowed, or unshadowed from the light centre when shadows are off)
//     + albedo · skyAmbient · AO            (AO = 1 when off)
//     + albedo · mean incoming one-bounce radiance (when diffuse is on)
// Output 0: linear HDR radiance; output 1: tone-mapped display value in [0, 1] (linear; PNG writing applies
// the sRGB transfer function).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "render/light.glsl"

layout(binding = CHCRT_UNIT_GBUFFER_POSITION) uniform sampler2D gbufferPosition;
layout(binding = CHCRT_UNIT_GBUFFER_NORMAL) uniform sampler2D gbufferNormal;
layout(binding = CHCRT_UNIT_GBUFFER_ALBEDO) uniform sampler2D gbufferAlbedo;
layout(binding = CHCRT_UNIT_GBUFFER_TRIANGLE) uniform usampler2D gbufferTriangle;
layout(binding = CHCRT_UNIT_ACCUM_DIRECT) uniform sampler2D accumDirect;
layout(binding = CHCRT_UNIT_ACCUM_AO) uniform sampler2D accumAo;
layout(binding = CHCRT_UNIT_ACCUM_INDIRECT) uniform sampler2D accumIndirect;

uniform bool shadowsEnabled;
uniform bool aoEnabled;
uniform bool diffuseEnabled;
uniform vec3 skyAmbient;      // ambient sky radiance, scaled by AO
uniform vec3 backgroundColor; // radiance of pixels that see no geometry
uniform float exposure;
// 0: full shading, 1: indirect only (albedo · incoming; Renderer::readIndirectImage), 2: AO only, 3: direct only
uniform int outputMode;

layout(location = 0) out vec4 outHdr;
layout(location = 1) out vec4 outDisplay;

// ACES filmic curve fit (Narkowicz 2015): cheap, monotonic, maps HDR into [0, 1).
vec3 toneMapAces(vec3 x) {
    return clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

vec3 mean(vec4 accumulated) {
    return accumulated.a > 0.0f ? accumulated.rgb / accumulated.a : vec3(0.0f);
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 radiance = outputMode == 1 ? vec3(0.0f) : backgroundColor; // indirect only: the background has none
    if (texelFetch(gbufferTriangle, pixel, 0).x != CHCRT_NO_HIT_ID) {
        vec3 albedo = texelFetch(gbufferAlbedo, pixel, 0).rgb;
        vec3 n = texelFetch(gbufferNormal, pixel, 0).xyz;
        vec3 direct;
        if (shadowsEnabled) {
            direct = mean(texelFetch(accumDirect, pixel, 0));
        } else {
            vec3 toLight = lightCorner + 0.5f * (lightEdgeU + lightEdgeV) - texelFetch(gbufferPosition, pixel, 0).xyz;
            float distance = length(toLight);
            direct = directLightSample(albedo, n, toLight / distance, distance);
        }
        float ao = aoEnabled ? mean(texelFetch(accumAo, pixel, 0)).r : 1.0f;
        vec3 indirect = diffuseEnabled ? albedo * mean(texelFetch(accumIndirect, pixel, 0)) : vec3(0.0f);
        vec3 ambient = albedo * skyAmbient * ao;
        if (outputMode == 1) {
            radiance = indirect;
        } else if (outputMode == 2) {
            radiance = vec3(ao);
        } else if (outputMode == 3) {
            radiance = direct;
        } else {
            radiance = direct + ambient + indirect;
        }
    }
    outHdr = vec4(radiance, 1.0f);
    outDisplay = vec4(outputMode == 2 ? radiance : toneMapAces(radiance * exposure), 1.0f);
}
