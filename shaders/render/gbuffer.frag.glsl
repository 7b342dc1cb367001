#version 450 core
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "render/bvh_triangles.glsl"
#include "render/material.glsl"

in vec3 worldPosition;
in vec3 worldNormal;
in vec2 texcoord;
flat in uint clusterFirst;

uniform vec3 cameraPosition;
uniform vec3 cameraForward;

layout(location = CHCRT_GBUFFER_OUT_POSITION) out vec4 outPosition;
layout(location = CHCRT_GBUFFER_OUT_NORMAL) out vec4 outNormal;
layout(location = CHCRT_GBUFFER_OUT_ALBEDO) out vec4 outAlbedo;
layout(location = CHCRT_GBUFFER_OUT_TRIANGLE) out uint outTriangle;

void main() {
    // gl_PrimitiveID counts from 0 in each draw of the multi-draw; the BVH triangle buffer maps the BVH-order index
    // back to the original id (texel 0's w, shared/bvh_layout.h).
    uint bvhIndex = clusterFirst + uint(gl_PrimitiveID);
    uint triangleId = floatBitsToUint(triangleTexel(int(bvhIndex) * CHCRT_TRI_TEXELS_PER_TRIANGLE).w);
    vec4 attr0 = attributeTexel(int(triangleId) * CHCRT_ATTR_TEXELS_PER_TRIANGLE);
    vec3 geometricNormal = attr0.xyz;
    // Shade with the interpolated normal, but orient it (and the geometric one) towards the camera: scenes are
    // not closed and secondary rays leave on the viewer's side.
    vec3 n = normalize(worldNormal);
    if (any(isnan(n))) {
        n = geometricNormal;
    }
    vec3 toCamera = cameraPosition - worldPosition;
    if (dot(geometricNormal, toCamera) < 0.0f) {
        geometricNormal = -geometricNormal;
    }
    if (dot(n, geometricNormal) < 0.0f) {
        n = -n;
    }
    outPosition = vec4(worldPosition, 1.0f);
    outNormal = vec4(n, dot(worldPosition - cameraPosition, cameraForward));
    outAlbedo = vec4(materialAlbedo(floatBitsToUint(attr0.w), texcoord, -1.0f), 1.0f);
    outTriangle = triangleId;
}
