#version 450 core
// Out-of-core traced primary visibility (CHC+RT §5.4 with the "Prim" column of Table 3): like
// raster/gbuffer_from_hits.frag.glsl, but the shading attributes of each pixel's hit come from per-pixel images
// filled on the host from the subtree that produced the hit (culling/outofcore/primary_resolve.h), because
// per-triangle buffers indexed by original id cannot exist for a scene that is not in core. Same G-buffer
// targets, same normal orientation rule; no textures (prepared scenes v1 store material colours only).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_UNIT_HIT) uniform usampler2D hits;
// Reuses the G-buffer units (this pass writes the G-buffer, it never samples it).
layout(binding = CHCRT_UNIT_GBUFFER_POSITION) uniform sampler2D pixelShadingNormals;   // interpolated vertex normal
layout(binding = CHCRT_UNIT_GBUFFER_NORMAL) uniform sampler2D pixelGeometricNormals;   // unit geometric normal
layout(binding = CHCRT_UNIT_GBUFFER_ALBEDO) uniform sampler2D pixelAlbedos;            // base colour

uniform vec3 cameraPosition;
uniform vec3 cameraForward;
uniform float nearPlane; // reversed infinite Z: depth = nearPlane / view depth

layout(location = CHCRT_GBUFFER_OUT_POSITION) out vec4 outPosition;
layout(location = CHCRT_GBUFFER_OUT_NORMAL) out vec4 outNormal;
layout(location = CHCRT_GBUFFER_OUT_ALBEDO) out vec4 outAlbedo;
layout(location = CHCRT_GBUFFER_OUT_TRIANGLE) out uint outTriangle;

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
    vec3 position = origin + uintBitsToFloat(hit.x) * direction;
    vec3 geometricNormal = texelFetch(pixelGeometricNormals, pixel, 0).xyz;
    vec3 n = texelFetch(pixelShadingNormals, pixel, 0).xyz;
    if (any(isnan(n)) || dot(n, n) == 0.0f) {
        n = geometricNormal;
    }
    // As the raster pass: the geometric normal turned towards the camera, the shading normal to its side.
    if (dot(geometricNormal, cameraPosition - position) < 0.0f) {
        geometricNormal = -geometricNormal;
    }
    if (dot(n, geometricNormal) < 0.0f) {
        n = -n;
    }
    float viewDepth = dot(position - cameraPosition, cameraForward);
    outPosition = vec4(position, 1.0f);
    outNormal = vec4(n, viewDepth);
    outAlbedo = vec4(texelFetch(pixelAlbedos, pixel, 0).rgb, 1.0f);
    outTriangle = triangleId;
    gl_FragDepth = nearPlane / max(viewDepth, nearPlane);
}
