#version 450 core
// Traced primary visibility (CHC+RT §5, the "Prim" column: primary rays traced instead of rasterised): resolves
// the primary rays' hit buffer into the same G-buffer targets that gbuffer.frag.glsl writes, so every later pass
// is unchanged. It reads only the hit buffer, the rays and per-triangle data addressed by the original triangle
// id (attributes, vertex normals, materials): nothing that needs the whole scene's geometry, which is what
// out-of-core scenes rely on. Misses write the G-buffer's clear values (background).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "render/material.glsl"
#include "render/vertex_normals.glsl"

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_UNIT_HIT) uniform usampler2D hits;

uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform float nearPlane;       // reversed infinite Z: depth = nearPlane / view depth (renderer/render/camera_math.h)
uniform float pixelSpread;     // 2 tan(fovY / 2) / height: a pixel's size at view depth 1
uniform float textureSide;     // side of the base-colour texture array in texels (level 0)

layout(location = CHCRT_GBUFFER_OUT_POSITION) out vec4 outPosition;
layout(location = CHCRT_GBUFFER_OUT_NORMAL) out vec4 outNormal;
layout(location = CHCRT_GBUFFER_OUT_ALBEDO) out vec4 outAlbedo;
layout(location = CHCRT_GBUFFER_OUT_TRIANGLE) out uint outTriangle;

vec3 vertexNormal(uint triangleId, int vertex) {
    uvec4 texel = normalTexel(int(triangleId) * CHCRT_NORMAL_TEXELS_PER_TRIANGLE + vertex);
    return vec3(texel.xyz) * (2.0f / 65535.0f) - 1.0f;
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    uvec4 hit = texelFetch(hits, pixel, 0);
    uint triangleId = hit.y;
    if (triangleId == CHCRT_NO_HIT_ID) {
        outPosition = vec4(0.0f);
        outNormal = vec4(0.0f);
        outAlbedo = vec4(0.0f);
        outTriangle = CHCRT_NO_HIT_ID;
        gl_FragDepth = 0.0f; // the reversed-Z clear value
        return;
    }
    vec3 origin = texelFetch(rayOrigins, pixel, 0).xyz;
    vec3 direction = texelFetch(rayDirections, pixel, 0).xyz;
    float t = uintBitsToFloat(hit.x);
    vec2 barycentrics = uintBitsToFloat(hit.zw);
    float w0 = 1.0f - barycentrics.x - barycentrics.y;
    vec3 position = origin + t * direction;

    int base = int(triangleId) * CHCRT_ATTR_TEXELS_PER_TRIANGLE;
    vec4 attr0 = attributeTexel(base);
    vec4 attr1 = attributeTexel(base + 1);
    vec4 attr2 = attributeTexel(base + 2);

    // Normals exactly as the raster pass orients them: the interpolated vertex normal (barycentric
    // interpolation at the hit = perspective-correct interpolation at the pixel centre), turned to the side of
    // the geometric normal that faces the camera.
    vec3 geometricNormal = attr0.xyz;
    vec3 n = normalize(w0 * vertexNormal(triangleId, 0) + barycentrics.x * vertexNormal(triangleId, 1) +
                       barycentrics.y * vertexNormal(triangleId, 2));
    if (any(isnan(n))) {
        n = geometricNormal;
    }
    if (dot(geometricNormal, cameraPosition - position) < 0.0f) {
        geometricNormal = -geometricNormal;
    }
    if (dot(n, geometricNormal) < 0.0f) {
        n = -n;
    }
    float viewDepth = dot(position - cameraPosition, cameraForward);

    // Mip level from the pixel's footprint on the surface (no screen-space derivatives in a full-screen pass):
    // footprint = view depth × pixel spread / |cos θ| world units, × texels per world unit of this triangle.
    vec2 uv = w0 * attr1.xy + barycentrics.x * attr1.zw + barycentrics.y * attr2.xy;
    float cosTheta = max(abs(dot(direction, geometricNormal)), 0.01f);
    float footprintTexels = viewDepth * pixelSpread / cosTheta * attr2.z * textureSide;
    float lod = max(log2(max(footprintTexels, 1e-8f)), 0.0f);

    outPosition = vec4(position, 1.0f);
    outNormal = vec4(n, viewDepth);
    outAlbedo = vec4(materialAlbedo(floatBitsToUint(attr0.w), uv, lod), 1.0f);
    outTriangle = triangleId;
    gl_FragDepth = nearPlane / max(viewDepth, nearPlane);
}
