#version 450 core
// Ray generation: one ray per pixel into the ray textures (origin + tmin, direction + tmax), CHC+RT §5.3.
// Host defines: RAY_TYPE (one of CHCRT_RAY_* from shared/render_layout.h).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "render/random.glsl"
#include "render/sampling.glsl"
#include "render/material.glsl"

layout(binding = CHCRT_UNIT_GBUFFER_POSITION) uniform sampler2D gbufferPosition;
layout(binding = CHCRT_UNIT_GBUFFER_NORMAL) uniform sampler2D gbufferNormal;
layout(binding = CHCRT_UNIT_GBUFFER_TRIANGLE) uniform usampler2D gbufferTriangle;
#ifndef CHCRT_PIXEL_GEOMETRIC_NORMALS
#define CHCRT_PIXEL_GEOMETRIC_NORMALS 0
#endif
#if CHCRT_PIXEL_GEOMETRIC_NORMALS
layout(binding = CHCRT_UNIT_PIXEL_GEOMETRIC_NORMAL) uniform sampler2D pixelGeometricNormals;
#endif
layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D previousRayOrigin;       // bounce shadow rays only
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D previousRayDirection; // bounce shadow rays only
layout(binding = CHCRT_UNIT_BOUNCE_HIT) uniform usampler2D bounceHit;              // bounce shadow rays only

uniform vec2 haltonSample;       // this pass's shared Halton point (renderer/render/halton.h)
uniform vec2 bounceHaltonSample; // the bounce shadow rays' point on the light
uniform uint seed;           // per-render seed (the per-pixel perturbation depends on it and the pixel only)
uniform float maxRotation;   // radians: per-pixel random rotation range (CHC+RT §5.3, Table 5)
uniform float rayLength;     // AO: ambient occlusion radius; diffuse: scene diagonal
uniform float offsetScale;   // origin offset along the geometric normal per unit of view distance
uniform vec3 cameraPosition;
uniform vec3 cameraForward;  // primary rays: camera basis scaled by the tangent of the half field of view
uniform vec3 cameraRight;
uniform vec3 cameraUp;
uniform vec2 viewportSize;
uniform vec3 lightCorner;
uniform vec3 lightEdgeU;
uniform vec3 lightEdgeV;

layout(location = CHCRT_RAYGEN_OUT_ORIGIN) out vec4 outOrigin;
layout(location = CHCRT_RAYGEN_OUT_DIRECTION) out vec4 outDirection;

// Inactive ray: tmax <= tmin. Tracers skip it and report a miss; shading knows why from the G-buffer.
void emitInactive() {
    outOrigin = vec4(0.0f);
    outDirection = vec4(0.0f, 0.0f, 1.0f, 0.0f);
}

// An inactive ray that keeps its surface point (shared/render_layout.h): another shadow, AO or diffuse ray set of the
// frame may have an active ray there, and a tracer that bounds every set of the frame at once needs all the points
// (TraceRequest::lightSweep, TraceRequest::hemisphereRays).
void emitInactiveAt(vec3 origin) {
    outOrigin = vec4(origin, 0.0f);
    outDirection = vec4(0.0f);
}

// Offset a surface point along its (oriented) geometric normal so the ray does not hit its own triangle;
// scaled with the distance to the camera because rasterised positions carry interpolation error of that order.
vec3 offsetOrigin(vec3 position, vec3 geometricNormal, float viewDistance) {
    float maxCoordinate = max(max(abs(position.x), abs(position.y)), abs(position.z));
    return position + geometricNormal * (offsetScale * viewDistance + 1e-5f * maxCoordinate);
}

// Shadow ray towards the area light: the pass's Halton point on the light, shifted per pixel (Cranley-Patterson
// rotation with a range that grows with maxRotation / 2π, so 0 = every pixel samples the same light point).
void emitShadowRay(vec3 origin, vec3 geometricNormal, uvec2 pixel, vec2 lightSample) {
    vec2 jitter = pixelRandom2(pixel, seed ^ 0x5bd1e995u) * (maxRotation / (2.0f * kPi));
    vec2 uv = fract(lightSample + jitter);
    vec3 target = lightCorner + uv.x * lightEdgeU + uv.y * lightEdgeV;
    vec3 toLight = target - origin;
    float distance = length(toLight);
    vec3 direction = toLight / distance;
    if (dot(direction, geometricNormal) <= 0.0f || dot(direction, cross(lightEdgeU, lightEdgeV)) >= 0.0f) {
        emitInactiveAt(origin); // light below the surface, or the point is behind the one-sided light: no contribution
        return;
    }
    outOrigin = vec4(origin, 0.0f);
    outDirection = vec4(direction, distance);
}

void generateRay() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);

#if RAY_TYPE == CHCRT_RAY_PRIMARY
    vec2 ndc = (vec2(pixel) + 0.5f) / viewportSize * 2.0f - 1.0f;
    vec3 direction = normalize(cameraForward + ndc.x * cameraRight + ndc.y * cameraUp);
    outOrigin = vec4(cameraPosition, 0.0f);
    outDirection = vec4(direction, CHCRT_NO_HIT_T);
#elif RAY_TYPE == CHCRT_RAY_BOUNCE_SHADOW
    uvec4 hit = texelFetch(bounceHit, ivec2(pixel), 0);
    vec4 rayDirection = texelFetch(previousRayDirection, ivec2(pixel), 0);
    uint hitId = hit.y;
    float hitT = uintBitsToFloat(hit.x);
    if (hitId == CHCRT_NO_HIT_ID || rayDirection.w <= texelFetch(previousRayOrigin, ivec2(pixel), 0).w) {
        emitInactive();
        return;
    }
    vec3 hitPosition = texelFetch(previousRayOrigin, ivec2(pixel), 0).xyz + hitT * rayDirection.xyz;
    vec3 hitNormal = hitGeometricNormal(hitId);
    if (dot(hitNormal, rayDirection.xyz) > 0.0f) {
        hitNormal = -hitNormal;
    }
    float travelled = hitT + distance(texelFetch(previousRayOrigin, ivec2(pixel), 0).xyz, cameraPosition);
    emitShadowRay(offsetOrigin(hitPosition, hitNormal, travelled), hitNormal, pixel, bounceHaltonSample);
#else
    if (texelFetch(gbufferTriangle, ivec2(pixel), 0).x == CHCRT_NO_HIT_ID) {
        emitInactive();
        return;
    }
    vec3 position = texelFetch(gbufferPosition, ivec2(pixel), 0).xyz;
    vec3 shadingNormal = texelFetch(gbufferNormal, ivec2(pixel), 0).xyz;
#if CHCRT_PIXEL_GEOMETRIC_NORMALS
    // Out of core (culling/outofcore/primary_resolve.h): no per-triangle buffer covers the scene.
    vec3 geometricNormal = texelFetch(pixelGeometricNormals, ivec2(pixel), 0).xyz;
#else
    vec3 geometricNormal = hitGeometricNormal(texelFetch(gbufferTriangle, ivec2(pixel), 0).x);
#endif
    if (dot(geometricNormal, cameraPosition - position) < 0.0f) {
        geometricNormal = -geometricNormal;
    }
    vec3 origin = offsetOrigin(position, geometricNormal, distance(position, cameraPosition));
#if RAY_TYPE == CHCRT_RAY_SHADOW
    emitShadowRay(origin, geometricNormal, pixel, haltonSample);
#else
    // AO and diffuse: the pass's shared cosine-weighted direction in tangent space, rotated per pixel.
    vec3 tangent, bitangent;
    buildTangentFrame(shadingNormal, tangent, bitangent);
    float rotation = pixelRandom2(pixel, seed).x * maxRotation;
    vec3 local = cosineHemisphere(haltonSample, rotation);
    vec3 direction = normalize(local.x * tangent + local.y * bitangent + local.z * shadingNormal);
    if (dot(direction, geometricNormal) <= 0.0f) {
        emitInactiveAt(origin); // below the geometric surface: counts as occluded; other sets may start here
        return;
    }
    outOrigin = vec4(origin, 0.0f);
    outDirection = vec4(direction, rayLength);
#endif
#endif
}

void main() {
    generateRay();
    // RayTextures::active: the tracers' early depth test skips what this marks 0, with the condition every tracer
    // uses for an active ray (tmax > tmin; a NaN bound counts as inactive in both places).
    gl_FragDepth = outDirection.w > outOrigin.w ? 1.0f : 0.0f;
}
