#version 450 core
// Accumulates one pass's traced samples into its effect's accumulation target (additive blending, alpha =
// sample count). Host defines: ACCUMULATE (CHCRT_RAY_SHADOW | CHCRT_RAY_AO | CHCRT_RAY_DIFFUSE).
//   shadow:  rgb += direct radiance of the light sample when unoccluded (inactive rays contribute 0)
//   ao:      r   += 1 when the AO ray escapes (inactive rays below the surface count as occluded)
//   diffuse: rgb += incoming radiance from the one-bounce hit = its albedo times the direct light there (with
//           the bounce shadow ray's visibility); cosine-weighted sampling makes the pixel's reflected indirect
//           radiance albedo · mean(incoming), applied in compose.frag.glsl.
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "render/material.glsl"
#include "render/light.glsl"

layout(binding = CHCRT_UNIT_GBUFFER_NORMAL) uniform sampler2D gbufferNormal;
layout(binding = CHCRT_UNIT_GBUFFER_ALBEDO) uniform sampler2D gbufferAlbedo;
layout(binding = CHCRT_UNIT_GBUFFER_TRIANGLE) uniform usampler2D gbufferTriangle;
layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_UNIT_HIT) uniform usampler2D hits;
layout(binding = CHCRT_UNIT_BOUNCE_HIT) uniform usampler2D bounceHits;

layout(location = 0) out vec4 outSample;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (texelFetch(gbufferTriangle, pixel, 0).x == CHCRT_NO_HIT_ID) {
        outSample = vec4(0.0f); // background: no samples
        return;
    }
    vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
    vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
    bool rayActive = directionTmax.w > originTmin.w;
    bool occluded = texelFetch(hits, pixel, 0).y != CHCRT_NO_HIT_ID;

#if ACCUMULATE == CHCRT_RAY_SHADOW
    vec3 radiance = vec3(0.0f);
    if (rayActive && !occluded) {
        radiance = directLightSample(texelFetch(gbufferAlbedo, pixel, 0).rgb, texelFetch(gbufferNormal, pixel, 0).xyz,
                                     directionTmax.xyz, directionTmax.w);
    }
    outSample = vec4(radiance, 1.0f);
#elif ACCUMULATE == CHCRT_RAY_AO
    outSample = vec4(rayActive && !occluded ? 1.0f : 0.0f, 0.0f, 0.0f, 1.0f);
#else
    // Here the ray textures and `hits` hold the bounce shadow rays; `bounceHits` the diffuse rays' hits.
    uvec4 bounceHit = texelFetch(bounceHits, pixel, 0);
    uint bounceId = bounceHit.y;
    vec3 incoming = vec3(0.0f);
    if (bounceId != CHCRT_NO_HIT_ID && rayActive && !occluded) {
        vec3 albedo = hitAlbedo(bounceId, uintBitsToFloat(bounceHit.zw));
        vec3 n = hitGeometricNormal(bounceId);
        if (dot(n, directionTmax.xyz) < 0.0f) {
            n = -n; // the shadow ray was only generated on the side the diffuse ray arrived from
        }
        incoming = directLightSample(albedo, n, directionTmax.xyz, directionTmax.w);
    }
    outSample = vec4(incoming, 1.0f);
#endif
}
